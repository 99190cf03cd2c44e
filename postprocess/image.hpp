#pragma once
// Pictures read and written through stb (Debian's libstb: stb_image, stb_image_write): a laboratory photograph in,
// figures for the report out. Row 0 is the top of the picture, as a viewer shows it.
#include "postprocess/error.hpp"

#include <cstddef>
#include <filesystem>
#include <vector>

namespace demsa::postprocess {

/// A grey image: `width` × `height` values in [0, 1], row 0 at the top, stored row by row.
struct GreyImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  ///< pixels[row * width + col]
  float at(int col, int row) const { return pixels[static_cast<std::size_t>(row) * width + col]; }
  float& at(int col, int row) { return pixels[static_cast<std::size_t>(row) * width + col]; }
};

/// Reads a BMP or PNG (grey, palette or colour; 8 or 16 bits) through stb_image into its luminance (ITU-R BT.601
/// weights for colour) in [0, 1]. A file that is not a readable image, not a regular file, or larger than
/// `max_pixels` throws ParseError naming the file and the reason.
///
/// What is refused, each with its reason: a path that does not exist, a directory, anything but a regular file (a
/// FIFO is refused before it is opened, so it never blocks), an empty file, a file larger than an image of
/// `max_pixels` pixels could be, a file that is neither a BMP ("BM") nor a PNG (its 8-byte signature) — stb_image
/// would otherwise guess a TGA in any bytes —, a BMP shorter than its pixel rows (stb_image reads zeros past the end
/// of a BMP instead of failing), and whatever stb_image cannot decode (a truncated PNG, a compression it lacks). An
/// alpha channel is ignored: the colour as stored.
GreyImage read_grey_image(const std::filesystem::path& file, long max_pixels = 64L * 1024 * 1024);

/// Writes an 8-bit grey PNG through stb_image_write, atomically enough for a case folder (a temporary file renamed).
/// Values are clipped to [0, 1] and rounded to 0..255. A failure to write throws std::system_error naming the file.
void write_grey_png(const std::filesystem::path& file, const GreyImage& image);

/// An 8-bit RGB image, for overlays in the report.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<unsigned char> pixels;  ///< 3 bytes per pixel, row 0 at the top
};
/// Writes an 8-bit RGB PNG, as write_grey_png.
void write_rgb_png(const std::filesystem::path& file, const RgbImage& image);

}  // namespace demsa::postprocess
