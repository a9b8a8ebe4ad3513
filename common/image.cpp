#include "common/image.h"

#include <cctype>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <png.h>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/fileio.h"

namespace tetmvs {
namespace fs = std::filesystem;

namespace {

std::uint32_t be16(const unsigned char* p) { return (std::uint32_t(p[0]) << 8) | p[1]; }
std::uint32_t be32(const unsigned char* p) { return (be16(p) << 16) | be16(p + 2); }
std::uint32_t le16(const unsigned char* p) { return (std::uint32_t(p[1]) << 8) | p[0]; }
std::uint32_t le32(const unsigned char* p) { return (le16(p + 2) << 16) | le16(p); }

// JPEG: the first start-of-frame segment after the markers before it.
std::optional<ImageSize> jpeg_size(std::ifstream& in) {
  in.seekg(2);
  unsigned char b[9];
  for (int segments = 0; segments < 1000 && in.read(reinterpret_cast<char*>(b), 4); ++segments) {
    if (b[0] != 0xFF) return std::nullopt;
    const int marker = b[1];
    const std::uint32_t len = be16(b + 2);
    if (len < 2) return std::nullopt;
    const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      if (!in.read(reinterpret_cast<char*>(b), 5)) return std::nullopt;
      return ImageSize{be16(b + 3), be16(b + 1)};
    }
    in.seekg(len - 2, std::ios::cur);
  }
  return std::nullopt;
}

// TIFF: tags 256 (width) and 257 (length) of the first image directory.
std::optional<ImageSize> tiff_size(std::ifstream& in, bool little) {
  const auto u16 = [&](const unsigned char* p) { return little ? le16(p) : be16(p); };
  const auto u32 = [&](const unsigned char* p) { return little ? le32(p) : be32(p); };
  unsigned char b[12];
  in.seekg(4);
  if (!in.read(reinterpret_cast<char*>(b), 4)) return std::nullopt;
  in.seekg(u32(b));
  if (!in.read(reinterpret_cast<char*>(b), 2)) return std::nullopt;
  const std::uint32_t n = u16(b);
  ImageSize s;
  for (std::uint32_t i = 0; i < n && i < 4096 && in.read(reinterpret_cast<char*>(b), 12); ++i) {
    const std::uint32_t tag = u16(b), type = u16(b + 2);
    const std::int64_t v = type == 3 ? u16(b + 8) : u32(b + 8);
    if (tag == 256) s.width = v;
    if (tag == 257) s.height = v;
  }
  if (s.width > 0 && s.height > 0) return s;
  return std::nullopt;
}

// PNM: "P1".."P6", then width and height as text (with # comments).
std::optional<ImageSize> pnm_size(std::ifstream& in) {
  in.seekg(2);
  std::int64_t v[2];
  for (auto& x : v) {
    int c = in.get();
    while (c != EOF && (std::isspace(c) || c == '#')) {
      if (c == '#')
        while (c != EOF && c != '\n') c = in.get();
      c = in.get();
    }
    if (c == EOF || !std::isdigit(c)) return std::nullopt;
    x = 0;
    while (c != EOF && std::isdigit(c) && x < (std::int64_t(1) << 40)) x = 10 * x + (c - '0'), c = in.get();
  }
  return ImageSize{v[0], v[1]};
}

}  // namespace

std::optional<ImageSize> read_image_size(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  unsigned char h[26] = {};
  if (!in.read(reinterpret_cast<char*>(h), 2)) return std::nullopt;
  in.read(reinterpret_cast<char*>(h + 2), 24);
  const std::streamsize got = 2 + in.gcount();
  in.clear();
  if (got >= 24 && h[0] == 0x89 && h[1] == 'P' && h[2] == 'N' && h[3] == 'G' && std::memcmp(h + 12, "IHDR", 4) == 0)
    return ImageSize{be32(h + 16), be32(h + 20)};
  if (h[0] == 0xFF && h[1] == 0xD8) return jpeg_size(in);
  if (got >= 26 && h[0] == 'B' && h[1] == 'M') {
    const auto w = static_cast<std::int32_t>(le32(h + 18)), hh = static_cast<std::int32_t>(le32(h + 22));
    return ImageSize{std::abs(std::int64_t(w)), std::abs(std::int64_t(hh))};
  }
  if (got >= 8 && ((h[0] == 'I' && h[1] == 'I' && h[2] == 42 && h[3] == 0) || (h[0] == 'M' && h[1] == 'M' && h[2] == 0 && h[3] == 42)))
    return tiff_size(in, h[0] == 'I');
  if (h[0] == 'P' && h[1] >= '1' && h[1] <= '6') return pnm_size(in);
  return std::nullopt;
}

cv::Mat rgb_to_grey(const cv::Mat& rgb) {
  require(rgb.type() == CV_8UC3, "rgb_to_grey: expected an 8-bit RGB image");
  cv::Mat g(rgb.rows, rgb.cols, CV_32F);
  for (int y = 0; y < rgb.rows; ++y) {
    const auto* s = rgb.ptr<cv::Vec3b>(y);
    float* d = g.ptr<float>(y);
    for (int x = 0; x < rgb.cols; ++x)
      d[x] = (0.299f * s[x][0] + 0.587f * s[x][1] + 0.114f * s[x][2]) / 255.0f;
  }
  return g;
}

std::string encode_png(const cv::Mat& img) {
  require(img.depth() == CV_8U && (img.channels() == 1 || img.channels() == 3 || img.channels() == 4) && !img.empty(),
          "encode_png: expected a non-empty 8-bit grey, RGB or RGBA image");
  png_image pi{};
  pi.version = PNG_IMAGE_VERSION;
  pi.width = static_cast<png_uint_32>(img.cols);
  pi.height = static_cast<png_uint_32>(img.rows);
  pi.format = img.channels() == 1 ? PNG_FORMAT_GRAY : img.channels() == 3 ? PNG_FORMAT_RGB : PNG_FORMAT_RGBA;
  const auto stride = static_cast<png_int_32>(img.step[0]);
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(pi, size, 0, img.data, stride, nullptr))
    fail("encode_png: ", pi.message);
  std::string out(size, '\0');
  if (!png_image_write_to_memory(&pi, out.data(), &size, 0, img.data, stride, nullptr))
    fail("encode_png: ", pi.message);
  out.resize(size);
  return out;
}

void write_png_rgb(const fs::path& file, const cv::Mat& rgb) { write_text_atomic(file, encode_png(rgb)); }

}  // namespace tetmvs
