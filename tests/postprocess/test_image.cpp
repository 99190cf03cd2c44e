// Pictures in and out (postprocess/image.hpp): BMP and PNG of every kind the drum's photographs come in, read back to
// known luminances, and each file that must be refused refused with its name and its reason.
#include "postprocess/error.hpp"
#include "postprocess/image.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <system_error>
#include <vector>

namespace demsa::drum_test_files {

// Writers of the files stb_image_write does not write (palette and 24-bit BMPs, 16-bit PNGs), byte by byte from the
// formats' specifications, so that the reader is tested against files it did not write. test_drum.cpp uses them too.

namespace {

void put16le(std::string& out, std::uint32_t v) {
  out += static_cast<char>(v & 0xFF);
  out += static_cast<char>((v >> 8) & 0xFF);
}
void put32le(std::string& out, std::uint32_t v) {
  put16le(out, v & 0xFFFF);
  put16le(out, v >> 16);
}
void put32be(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((v >> shift) & 0xFF);
}

/// BITMAPFILEHEADER + BITMAPINFOHEADER (Microsoft, "Bitmap Storage").
std::string bmp_headers(int width, int height, int bits, int palette_entries, bool top_down) {
  const std::uint32_t row = static_cast<std::uint32_t>((width * bits + 31) / 32 * 4);
  const std::uint32_t offset = 14 + 40 + 4 * static_cast<std::uint32_t>(palette_entries);
  const std::uint32_t pixels = row * static_cast<std::uint32_t>(height);
  std::string out = "BM";
  put32le(out, offset + pixels);
  put32le(out, 0);
  put32le(out, offset);
  put32le(out, 40);
  put32le(out, static_cast<std::uint32_t>(width));
  put32le(out, static_cast<std::uint32_t>(top_down ? -height : height));
  put16le(out, 1);
  put16le(out, static_cast<std::uint32_t>(bits));
  put32le(out, 0);  // BI_RGB
  put32le(out, pixels);
  put32le(out, 2835);  // 72 dpi
  put32le(out, 2835);
  put32le(out, static_cast<std::uint32_t>(palette_entries));
  put32le(out, 0);
  return out;
}

std::uint32_t crc32(const std::string& bytes) {
  // The CRC of the PNG specification (ISO/IEC 15948, annex D).
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xFFFFFFFFu;
}

void png_chunk(std::string& out, const std::string& type, const std::string& data) {
  put32be(out, static_cast<std::uint32_t>(data.size()));
  out += type + data;
  put32be(out, crc32(type + data));
}

}  // namespace

/// An 8-bit palette BMP of `index` (row 0 at the top) with the palette's (r, g, b) entries.
std::string palette_bmp(int width, int height, const std::vector<unsigned char>& index,
                        const std::vector<std::array<unsigned char, 3>>& palette, bool top_down = false) {
  std::string out = bmp_headers(width, height, 8, static_cast<int>(palette.size()), top_down);
  for (const auto& c : palette) out += {static_cast<char>(c[2]), static_cast<char>(c[1]), static_cast<char>(c[0]), 0};
  const int row_bytes = (width * 8 + 31) / 32 * 4;
  for (int k = 0; k < height; ++k) {
    const int row = top_down ? k : height - 1 - k;  // BMP rows are stored bottom-up unless the height is negative
    for (int col = 0; col < width; ++col) out += static_cast<char>(index[static_cast<std::size_t>(row) * width + col]);
    out.append(static_cast<std::size_t>(row_bytes - width), '\0');
  }
  return out;
}

/// A grey image as an 8-bit palette BMP with a grey palette (the GranuDrum's files).
std::string grey_bmp(const postprocess::GreyImage& image) {
  std::vector<std::array<unsigned char, 3>> palette(256);
  for (int i = 0; i < 256; ++i)
    palette[i] = {static_cast<unsigned char>(i), static_cast<unsigned char>(i), static_cast<unsigned char>(i)};
  std::vector<unsigned char> index(image.pixels.size());
  for (std::size_t i = 0; i < index.size(); ++i)
    index[i] = static_cast<unsigned char>(std::lround(std::clamp(image.pixels[i], 0.0f, 1.0f) * 255.0f));
  return palette_bmp(image.width, image.height, index, palette);
}

/// A 24-bit BMP of (r, g, b) pixels, row 0 at the top.
std::string rgb_bmp(int width, int height, const std::vector<std::array<unsigned char, 3>>& rgb) {
  std::string out = bmp_headers(width, height, 24, 0, false);
  const int row_bytes = (width * 24 + 31) / 32 * 4;
  for (int row = height - 1; row >= 0; --row) {
    for (int col = 0; col < width; ++col) {
      const auto& c = rgb[static_cast<std::size_t>(row) * width + col];
      out += {static_cast<char>(c[2]), static_cast<char>(c[1]), static_cast<char>(c[0])};
    }
    out.append(static_cast<std::size_t>(row_bytes - 3 * width), '\0');
  }
  return out;
}

/// A 16-bit PNG (colour type 0: grey, `channels` 1; 2: RGB, `channels` 3) of samples row by row, its zlib stream in
/// stored (uncompressed) deflate blocks (RFC 1950, RFC 1951 §3.2.4).
std::string png16(int width, int height, int channels, const std::vector<std::uint16_t>& samples) {
  std::string raw;
  for (int row = 0; row < height; ++row) {
    raw += '\0';  // filter type None
    for (int k = 0; k < width * channels; ++k) {
      const std::uint16_t v = samples[static_cast<std::size_t>(row) * width * channels + k];
      raw += static_cast<char>(v >> 8);
      raw += static_cast<char>(v & 0xFF);
    }
  }
  std::string z = "\x78\x01";
  for (std::size_t at = 0; at < raw.size() || at == 0; at += 65535) {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - at);
    z += static_cast<char>(at + n >= raw.size() ? 1 : 0);
    put16le(z, static_cast<std::uint32_t>(n));
    put16le(z, static_cast<std::uint32_t>(~n & 0xFFFF));
    z += raw.substr(at, n);
    if (at + n >= raw.size()) break;
  }
  std::uint32_t a = 1, b = 0;  // Adler-32
  for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
  put32be(z, b << 16 | a);
  std::string ihdr;
  put32be(ihdr, static_cast<std::uint32_t>(width));
  put32be(ihdr, static_cast<std::uint32_t>(height));
  ihdr += {16, static_cast<char>(channels == 3 ? 2 : 0), 0, 0, 0};
  std::string out = "\x89PNG\r\n\x1a\n";
  png_chunk(out, "IHDR", ihdr);
  png_chunk(out, "IDAT", z);
  png_chunk(out, "IEND", "");
  return out;
}

}  // namespace demsa::drum_test_files

namespace demsa {
namespace {

using postprocess::GreyImage;
using postprocess::ParseError;
using postprocess::read_grey_image;
namespace files = drum_test_files;

float bt601(int r, int g, int b) { return (0.299f * r + 0.587f * g + 0.114f * b) / 255.0f; }

TEST(ImageRead, GreyPngWrittenAndReadBack) {
  test::TempDir tmp;
  GreyImage image{5, 3, {}};
  for (int i = 0; i < 15; ++i) image.pixels.push_back(static_cast<float>(i * 17) / 255.0f);
  postprocess::write_grey_png(tmp / "grey.png", image);
  const GreyImage back = read_grey_image(tmp / "grey.png");
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  for (int i = 0; i < 15; ++i) EXPECT_FLOAT_EQ(back.pixels[i], image.pixels[i]) << i;
  EXPECT_FLOAT_EQ(back.at(4, 0), 4 * 17 / 255.0f);  // row 0 is the top
  EXPECT_FLOAT_EQ(back.at(0, 2), 10 * 17 / 255.0f);
}

TEST(ImageRead, GreyPaletteBmpBottomUpAndTopDown) {
  test::TempDir tmp;
  GreyImage image{7, 4, {}};  // 7 columns: rows padded to 8 bytes
  for (int i = 0; i < 28; ++i) image.pixels.push_back(static_cast<float>(9 * i) / 255.0f);
  test::write_file(tmp / "up.bmp", files::grey_bmp(image));
  std::vector<std::array<unsigned char, 3>> grey(256);
  for (int i = 0; i < 256; ++i)
    grey[i] = {static_cast<unsigned char>(i), static_cast<unsigned char>(i), static_cast<unsigned char>(i)};
  std::vector<unsigned char> index;
  for (int i = 0; i < 28; ++i) index.push_back(static_cast<unsigned char>(9 * i));
  test::write_file(tmp / "down.bmp", files::palette_bmp(7, 4, index, grey, true));
  for (const char* name : {"up.bmp", "down.bmp"}) {
    const GreyImage back = read_grey_image(tmp / name);
    ASSERT_EQ(back.width, 7) << name;
    ASSERT_EQ(back.height, 4) << name;
    for (int i = 0; i < 28; ++i) EXPECT_FLOAT_EQ(back.pixels[i], image.pixels[i]) << name << " pixel " << i;
  }
}

TEST(ImageRead, ColourPaletteBmpGivesBt601Luminance) {
  test::TempDir tmp;
  const std::vector<std::array<unsigned char, 3>> palette = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {40, 80, 200}};
  test::write_file(tmp / "colour.bmp", files::palette_bmp(2, 2, {0, 1, 2, 3}, palette));
  const GreyImage back = read_grey_image(tmp / "colour.bmp");
  EXPECT_NEAR(back.at(0, 0), bt601(255, 0, 0), 1e-6);
  EXPECT_NEAR(back.at(1, 0), bt601(0, 255, 0), 1e-6);
  EXPECT_NEAR(back.at(0, 1), bt601(0, 0, 255), 1e-6);
  EXPECT_NEAR(back.at(1, 1), bt601(40, 80, 200), 1e-6);
}

TEST(ImageRead, RgbBmpAndRgbPngGiveBt601Luminance) {
  test::TempDir tmp;
  const std::vector<std::array<unsigned char, 3>> rgb = {{255, 0, 0},  {0, 255, 0},    {0, 0, 255},
                                                         {10, 20, 30}, {200, 100, 50}, {255, 255, 255}};
  test::write_file(tmp / "rgb.bmp", files::rgb_bmp(3, 2, rgb));
  postprocess::RgbImage image{3, 2, {}};
  for (const auto& c : rgb) image.pixels.insert(image.pixels.end(), c.begin(), c.end());
  postprocess::write_rgb_png(tmp / "rgb.png", image);
  for (const char* name : {"rgb.bmp", "rgb.png"}) {
    const GreyImage back = read_grey_image(tmp / name);
    ASSERT_EQ(back.width, 3) << name;
    for (std::size_t i = 0; i < rgb.size(); ++i)
      EXPECT_NEAR(back.pixels[i], bt601(rgb[i][0], rgb[i][1], rgb[i][2]), 1e-6) << name << " pixel " << i;
  }
}

TEST(ImageRead, SixteenBitPngKeepsItsDepth) {
  test::TempDir tmp;
  // 1234 and 1235 are one 8-bit level apart from nothing: an 8-bit read would give 4/255 for both.
  test::write_file(tmp / "grey16.png", files::png16(2, 2, 1, {1234, 1235, 65535, 0}));
  const GreyImage grey = read_grey_image(tmp / "grey16.png");
  EXPECT_NEAR(grey.at(0, 0), 1234.0 / 65535.0, 1e-7);
  EXPECT_NEAR(grey.at(1, 0), 1235.0 / 65535.0, 1e-7);
  EXPECT_FLOAT_EQ(grey.at(0, 1), 1.0f);
  EXPECT_FLOAT_EQ(grey.at(1, 1), 0.0f);
  test::write_file(tmp / "rgb16.png", files::png16(1, 1, 3, {60000, 30000, 1000}));
  EXPECT_NEAR(read_grey_image(tmp / "rgb16.png").at(0, 0), (0.299 * 60000 + 0.587 * 30000 + 0.114 * 1000) / 65535.0,
              1e-6);
}

// ---------------------------------------------------------------------------------------------- refused files

/// A 40 × 30 grey BMP of a gradient.
std::string gradient_bmp() {
  GreyImage image{40, 30, {}};
  for (int i = 0; i < 1200; ++i) image.pixels.push_back(static_cast<float>(i % 97) / 96.0f);
  return files::grey_bmp(image);
}

TEST(ImageRefuses, TextFileIsNotAnImage) {
  test::TempDir tmp;
  test::write_file(tmp / "notes.bmp", "angle 41.2 deg\nthis is not a picture\n");
  const std::string message = test::message_of<ParseError>([&] { read_grey_image(tmp / "notes.bmp"); });
  EXPECT_NE(message.find((tmp / "notes.bmp").string()), std::string::npos) << message;
  EXPECT_NE(message.find("not a BMP or PNG"), std::string::npos) << message;
}

TEST(ImageRefuses, TruncatedBmp) {
  test::TempDir tmp;
  const std::string bytes = gradient_bmp();
  test::write_file(tmp / "whole.bmp", bytes);
  ASSERT_NO_THROW(read_grey_image(tmp / "whole.bmp"));
  test::write_file(tmp / "cut.bmp", bytes.substr(0, bytes.size() - 100));
  const std::string message = test::message_of<ParseError>([&] { read_grey_image(tmp / "cut.bmp"); });
  EXPECT_NE(message.find((tmp / "cut.bmp").string()), std::string::npos) << message;
  EXPECT_NE(message.find("truncated BMP"), std::string::npos) << message;
}

TEST(ImageRefuses, TruncatedPng) {
  test::TempDir tmp;
  GreyImage image{64, 64, {}};
  for (int i = 0; i < 64 * 64; ++i) image.pixels.push_back(static_cast<float>((i * 7919) % 256) / 255.0f);
  postprocess::write_grey_png(tmp / "whole.png", image);
  const std::string bytes = test::read_file(tmp / "whole.png");
  test::write_file(tmp / "cut.png", bytes.substr(0, bytes.size() / 2));
  const std::string message = test::message_of<ParseError>([&] { read_grey_image(tmp / "cut.png"); });
  EXPECT_NE(message.find((tmp / "cut.png").string()), std::string::npos) << message;
  EXPECT_NE(message.find("PNG"), std::string::npos) << message;
}

TEST(ImageRefuses, Directory) {
  test::TempDir tmp;
  std::filesystem::create_directory(tmp / "photo.png");
  const std::string message = test::message_of<ParseError>([&] { read_grey_image(tmp / "photo.png"); });
  EXPECT_NE(message.find((tmp / "photo.png").string()), std::string::npos) << message;
  EXPECT_NE(message.find("is a directory"), std::string::npos) << message;
}

TEST(ImageRefuses, FifoWithoutBlocking) {
  test::TempDir tmp;
  ASSERT_EQ(::mkfifo((tmp / "pipe.bmp").c_str(), 0600), 0);
  // Opening a FIFO for reading blocks until a writer comes: the reader must refuse it before it opens it.
  const std::string message = test::message_of<ParseError>([&] { read_grey_image(tmp / "pipe.bmp"); });
  EXPECT_NE(message.find((tmp / "pipe.bmp").string()), std::string::npos) << message;
  EXPECT_NE(message.find("not a regular file"), std::string::npos) << message;
}

TEST(ImageRefuses, MissingAndEmptyFiles) {
  test::TempDir tmp;
  std::string message = test::message_of<ParseError>([&] { read_grey_image(tmp / "absent.png"); });
  EXPECT_NE(message.find((tmp / "absent.png").string() + ": no such file"), std::string::npos) << message;
  test::write_file(tmp / "empty.png", "");
  message = test::message_of<ParseError>([&] { read_grey_image(tmp / "empty.png"); });
  EXPECT_NE(message.find((tmp / "empty.png").string() + ": is empty"), std::string::npos) << message;
}

TEST(ImageRefuses, MorePixelsThanAllowed) {
  test::TempDir tmp;
  test::write_file(tmp / "big.bmp", gradient_bmp());
  EXPECT_NO_THROW(read_grey_image(tmp / "big.bmp", 1200));
  std::string message = test::message_of<ParseError>([&] { read_grey_image(tmp / "big.bmp", 1199); });
  EXPECT_NE(message.find((tmp / "big.bmp").string()), std::string::npos) << message;
  EXPECT_NE(message.find("40 × 30 pixels: more than the 1199"), std::string::npos) << message;
  // A file far larger than any image of that many pixels is refused before it is read.
  test::write_file(tmp / "huge.png", std::string(2 << 20, 'x'));
  message = test::message_of<ParseError>([&] { read_grey_image(tmp / "huge.png", 10); });
  EXPECT_NE(message.find("larger than an image this reader accepts"), std::string::npos) << message;
}

TEST(ImageWrite, UnwritableFolderNamesTheFile) {
  test::TempDir tmp;
  const GreyImage image{2, 2, {0.0f, 0.5f, 1.0f, 0.25f}};
  try {
    postprocess::write_grey_png(tmp / "absent" / "figure.png", image);
    FAIL() << "wrote into a missing folder";
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find("figure.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(tmp / "absent"));
  postprocess::write_grey_png(tmp / "figure.png", image);  // and the rename leaves no temporary behind
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(tmp.path()), std::filesystem::directory_iterator()), 1);
}

}  // namespace
}  // namespace demsa
