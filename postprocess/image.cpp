#include "postprocess/image.hpp"

#include <fcntl.h>
#include <stb_image.h>
#include <stb_image_write.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <system_error>

namespace demsa::postprocess {

namespace {

constexpr std::array<unsigned char, 8> k_png_signature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
/// Headers, palettes and chunks beyond the pixels: a file larger than its pixels at 8 bytes each (16-bit RGBA, the
/// largest stb_image reads) plus this is no image of `max_pixels` pixels.
constexpr std::uintmax_t k_header_slack = std::uintmax_t{1} << 20;

enum class Format { bmp, png };

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

std::uint32_t le32(const std::vector<unsigned char>& b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
         static_cast<std::uint32_t>(b[at + 2]) << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}
std::uint32_t le16(const std::vector<unsigned char>& b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8;
}

/// The file's bytes, after refusing what is not a regular file of a plausible size. The status is checked before the
/// file is opened (a FIFO would block an open for reading), and the opened descriptor is checked again (O_NONBLOCK,
/// fstat), so a path swapped in between cannot block either.
std::vector<unsigned char> read_bytes(const std::filesystem::path& file, const std::string& name,
                                      std::uintmax_t max_bytes) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (status.type() == std::filesystem::file_type::not_found) throw ParseError(name, 0, "no such file");
  if (ec) throw ParseError(name, 0, fmt::format("cannot read: {}", ec.message()));
  if (std::filesystem::is_directory(status)) throw ParseError(name, 0, "is a directory, not an image");
  if (!std::filesystem::is_regular_file(status))
    throw ParseError(name, 0, "is not a regular file (a FIFO, socket or device), not an image");

  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw ParseError(name, 0, fmt::format("cannot open: {}", std::strerror(errno)));
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw ParseError(name, 0, fmt::format("cannot read: {}", std::strerror(errno)));
  if (!S_ISREG(st.st_mode)) throw ParseError(name, 0, "is not a regular file, not an image");
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size == 0) throw ParseError(name, 0, "is empty, not an image");
  if (size > max_bytes)
    throw ParseError(
        name, 0, fmt::format("{} bytes: larger than an image this reader accepts ({} bytes at most)", size, max_bytes));
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw ParseError(name, 0, fmt::format("cannot read: {}", std::strerror(errno)));
    if (n == 0) break;  // shrank while read: judged by what was read
    done += static_cast<std::size_t>(n);
  }
  bytes.resize(done);
  return bytes;
}

Format format_of(const std::vector<unsigned char>& bytes, const std::string& name) {
  if (bytes.size() >= k_png_signature.size() &&
      std::equal(k_png_signature.begin(), k_png_signature.end(), bytes.begin()))
    return Format::png;
  if (bytes.size() >= 2 && bytes[0] == 'B' && bytes[1] == 'M') return Format::bmp;
  throw ParseError(name, 0, "not a BMP or PNG image (neither a \"BM\" nor a PNG signature at its start)");
}

/// stb_image reads past the end of a BMP as zeros rather than failing, so a BMP's length is checked against its
/// header (Microsoft, "Bitmap Storage", BITMAPFILEHEADER and BITMAPINFOHEADER/BITMAPCOREHEADER): the pixel rows start
/// at bfOffBits and each row of an uncompressed bitmap takes ⌈width·bits/32⌉ 4-byte words.
void check_bmp_length(const std::vector<unsigned char>& b, const std::string& name) {
  if (b.size() < 26)
    throw ParseError(name, 0, fmt::format("truncated BMP: {} bytes, shorter than its header", b.size()));
  const std::uint32_t offset = le32(b, 10);
  const std::uint32_t header = le32(b, 14);
  std::int64_t width = 0, height = 0, bits = 0, compression = 0;
  if (header == 12) {  // BITMAPCOREHEADER (OS/2)
    width = le16(b, 18), height = le16(b, 20), bits = le16(b, 24);
  } else {
    if (b.size() < 34)
      throw ParseError(name, 0, fmt::format("truncated BMP: {} bytes, shorter than its header", b.size()));
    width = static_cast<std::int32_t>(le32(b, 18)), height = static_cast<std::int32_t>(le32(b, 22));
    bits = le16(b, 28), compression = le32(b, 30);
  }
  // BI_RGB (0) and BI_BITFIELDS (3) store whole rows; run-length encoded bitmaps are left to stb_image, which
  // refuses them.
  if (compression != 0 && compression != 3) return;
  const std::int64_t row_bytes = (std::abs(width) * bits + 31) / 32 * 4;
  const std::int64_t needed = static_cast<std::int64_t>(offset) + row_bytes * std::abs(height);
  if (static_cast<std::int64_t>(b.size()) < needed)
    throw ParseError(name, 0,
                     fmt::format("truncated BMP: {} bytes, its {} rows of {} bytes from byte {} need {}", b.size(),
                                 std::abs(height), row_bytes, offset, needed));
}

float luminance(const std::uint16_t* p, int channels, float scale) {
  // ITU-R BT.601 luma weights for colour; grey (with or without alpha) as it is; alpha ignored.
  if (channels < 3) return static_cast<float>(p[0]) * scale;
  return (0.299f * static_cast<float>(p[0]) + 0.587f * static_cast<float>(p[1]) + 0.114f * static_cast<float>(p[2])) *
         scale;
}
float luminance(const unsigned char* p, int channels, float scale) {
  if (channels < 3) return static_cast<float>(p[0]) * scale;
  return (0.299f * static_cast<float>(p[0]) + 0.587f * static_cast<float>(p[1]) + 0.114f * static_cast<float>(p[2])) *
         scale;
}

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  const auto* bytes = static_cast<const unsigned char*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

/// The encoded file written beside its final name and renamed over it, so a reader never sees half a picture.
void write_atomically(const std::filesystem::path& file, const std::vector<unsigned char>& bytes) {
  std::filesystem::path temporary = file;
  temporary += fmt::format(".tmp-{}", ::getpid());
  std::FILE* out = std::fopen(temporary.c_str(), "wb");
  if (out == nullptr) throw std::system_error(errno, std::generic_category(), "cannot write " + temporary.string());
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), out) == bytes.size();
  const int write_errno = errno;
  if (std::fclose(out) != 0 || !written) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::system_error(written ? errno : write_errno, std::generic_category(), "cannot write " + file.string());
  }
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::system_error(ec, "cannot write " + file.string());
  }
}

void write_png(const std::filesystem::path& file, int width, int height, int channels,
               const std::vector<unsigned char>& pixels) {
  assert(width > 0 && height > 0 && pixels.size() == static_cast<std::size_t>(width) * height * channels);
  std::vector<unsigned char> encoded;
  if (stbi_write_png_to_func(append_bytes, &encoded, width, height, channels, pixels.data(), width * channels) == 0)
    throw std::system_error(std::make_error_code(std::errc::not_enough_memory),
                            "cannot encode the PNG of " + file.string());
  write_atomically(file, encoded);
}

}  // namespace

GreyImage read_grey_image(const std::filesystem::path& file, long max_pixels) {
  assert(max_pixels > 0);
  const std::string name = file.string();
  const std::uintmax_t max_bytes = static_cast<std::uintmax_t>(max_pixels) * 8 + k_header_slack;
  const std::vector<unsigned char> bytes = read_bytes(file, name, max_bytes);
  const Format format = format_of(bytes, name);
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw ParseError(name, 0, fmt::format("{} bytes: larger than stb_image reads", bytes.size()));
  const int length = static_cast<int>(bytes.size());

  int width = 0, height = 0, channels = 0;
  if (stbi_info_from_memory(bytes.data(), length, &width, &height, &channels) == 0)
    throw ParseError(
        name, 0,
        fmt::format("not a readable {} image: {}", format == Format::png ? "PNG" : "BMP", stbi_failure_reason()));
  // stb_image's info gives a top-down BMP's height negative, as its header stores it.
  width = std::abs(width), height = std::abs(height);
  if (static_cast<long long>(width) * height > max_pixels)
    throw ParseError(name, 0,
                     fmt::format("{} × {} pixels: more than the {} this reader accepts", width, height, max_pixels));
  if (format == Format::bmp) check_bmp_length(bytes, name);

  GreyImage image;
  int w = 0, h = 0, n = 0;
  if (stbi_is_16_bit_from_memory(bytes.data(), length) != 0) {
    const std::unique_ptr<std::uint16_t, StbFree> data(stbi_load_16_from_memory(bytes.data(), length, &w, &h, &n, 0));
    if (!data) throw ParseError(name, 0, fmt::format("cannot decode the PNG: {}", stbi_failure_reason()));
    image.width = w, image.height = h;
    image.pixels.resize(static_cast<std::size_t>(w) * h);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
      image.pixels[i] = luminance(data.get() + i * n, n, 1.0f / 65535.0f);
  } else {
    const std::unique_ptr<unsigned char, StbFree> data(stbi_load_from_memory(bytes.data(), length, &w, &h, &n, 0));
    if (!data)
      throw ParseError(
          name, 0,
          fmt::format("cannot decode the {}: {}", format == Format::png ? "PNG" : "BMP", stbi_failure_reason()));
    image.width = w, image.height = h;
    image.pixels.resize(static_cast<std::size_t>(w) * h);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
      image.pixels[i] = luminance(data.get() + i * n, n, 1.0f / 255.0f);
  }
  if (w != width || h != height)
    throw ParseError(name, 0,
                     fmt::format("decoded as {} × {} pixels where its header says {} × {}", w, h, width, height));
  for (float& v : image.pixels) v = std::clamp(v, 0.0f, 1.0f);  // rounding of the weighted sum
  return image;
}

void write_grey_png(const std::filesystem::path& file, const GreyImage& image) {
  std::vector<unsigned char> bytes(image.pixels.size());
  for (std::size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<unsigned char>(std::lround(std::clamp(image.pixels[i], 0.0f, 1.0f) * 255.0f));
  write_png(file, image.width, image.height, 1, bytes);
}

void write_rgb_png(const std::filesystem::path& file, const RgbImage& image) {
  write_png(file, image.width, image.height, 3, image.pixels);
}

}  // namespace demsa::postprocess
