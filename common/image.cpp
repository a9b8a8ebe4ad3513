#include "common/image.h"

#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "common/budget.h"
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

// While one is alive (in any thread), what the image libraries print on stderr (libpng's
// and libjpeg's own "error" and "warning" lines) goes to a scratch file that is dropped:
// the readers report a failure themselves, in one line naming the file. Guards of several
// threads overlap: the first redirects stderr, the last restores it.
class DecoderMessagesDropped {
 public:
  DecoderMessagesDropped() {
    std::lock_guard<std::mutex> lock(mu());
    if (count()++ > 0) return;
    std::fflush(stderr);
    saved() = ::dup(2);
    FILE* scratch = std::tmpfile();
    if (saved() >= 0 && scratch) {
      ::dup2(::fileno(scratch), 2);
      std::fclose(scratch);  // fd 2 keeps the (unlinked) file open
    } else if (scratch) {
      std::fclose(scratch);
    }
  }
  ~DecoderMessagesDropped() {
    std::lock_guard<std::mutex> lock(mu());
    if (--count() > 0) return;
    std::fflush(stderr);
    if (saved() >= 0) {
      ::dup2(saved(), 2);
      ::close(saved());
      saved() = -1;
    }
  }
  DecoderMessagesDropped(const DecoderMessagesDropped&) = delete;
  DecoderMessagesDropped& operator=(const DecoderMessagesDropped&) = delete;

 private:
  static std::mutex& mu() {
    static std::mutex m;
    return m;
  }
  static int& count() {
    static int c = 0;
    return c;
  }
  static int& saved() {
    static int fd = -1;
    return fd;
  }
};

// Refuses an image whose header declares more pixels than the stage's budget holds
// (decoding needs about 4 bytes a pixel, the RGB copy 3 more).
void check_image_header(const fs::path& file) {
  if (const auto s = read_image_size(file)) {
    std::ostringstream what;
    what << file.string() << ": the image header (" << s->width << " x " << s->height << " pixels)";
    check_declared_bytes(7.0 * static_cast<double>(s->width) * static_cast<double>(s->height), what.str());
  }
}

// cv::imread with OpenCV's own refusals (e.g. more than 2^30 pixels) as an Error naming the file.
cv::Mat read_image(const fs::path& file, const char* what) {
  if (!fs::exists(file)) fail(file.string(), ": ", what, " file is missing");
  check_regular_file(file);
  check_image_header(file);
  note_input(file);
  cv::Mat m;
  try {
    DecoderMessagesDropped quiet;
    m = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    fail(file.string(), ": cannot decode ", what, " (", e.err, ")");
  }
  if (m.empty()) fail(file.string(), ": cannot decode ", what, " (corrupt or unsupported format)");
  return m;
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

cv::Mat load_rgb(const fs::path& file) {
  cv::Mat m = read_image(file, "image");
  if (m.depth() != CV_8U) fail(file.string(), ": image must be 8-bit per channel");
  cv::Mat rgb;
  if (m.channels() == 1) cv::cvtColor(m, rgb, cv::COLOR_GRAY2RGB);
  else if (m.channels() == 3) cv::cvtColor(m, rgb, cv::COLOR_BGR2RGB);
  else if (m.channels() == 4) cv::cvtColor(m, rgb, cv::COLOR_BGRA2RGB);
  else fail(file.string(), ": unsupported channel count ", m.channels());
  return rgb;
}

cv::Mat load_mask(const fs::path& file) {
  cv::Mat m = read_image(file, "mask");
  std::vector<cv::Mat> ch;
  cv::split(m, ch);
  cv::Mat first;
  ch[0].convertTo(first, CV_32F, m.depth() == CV_16U ? 1.0 / 257.0 : 1.0);
  cv::Mat out = first > 127.0f;
  return out;
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

void write_png_rgb(const fs::path& file, const cv::Mat& rgb) {
  cv::Mat out;
  if (rgb.channels() == 3) cv::cvtColor(rgb, out, cv::COLOR_RGB2BGR);
  else out = rgb;
  std::vector<uchar> buf;
  if (!cv::imencode(".png", out, buf)) fail(file.string(), ": PNG encoding failed");
  write_text_atomic(file, std::string(buf.begin(), buf.end()));
}

}  // namespace tetmvs
