// Decoding image files (OpenCV's imgcodecs) apart from the rest of common/image.cpp: only
// the programs that read photos and masks load the codec libraries (with Debian's OpenCV,
// GDAL's hundred-odd shared libraries, a tenth of a second at every start-up): this file and
// those that call it form the library common_io, and programs link --as-needed
// (CMakeLists.txt).
#include <unistd.h>

#include <cstdio>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/image.h"

namespace tetmvs {
namespace fs = std::filesystem;

namespace {

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

}  // namespace tetmvs
