#include "io/image_input.h"

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <mutex>

namespace clothfit {
namespace {

// Points file descriptor 2 at /dev/null while alive. One at a time: the
// saved descriptor must be the real stderr.
class QuietStderr {
 public:
  QuietStderr() : lock_(Mutex()) {
    std::fflush(stderr);
    saved_ = dup(STDERR_FILENO);
    const int null = open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (saved_ >= 0 && null >= 0) dup2(null, STDERR_FILENO);
    if (null >= 0) close(null);
  }
  ~QuietStderr() {
    std::fflush(stderr);
    if (saved_ >= 0) {
      dup2(saved_, STDERR_FILENO);
      close(saved_);
    }
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  static std::mutex& Mutex() {
    static std::mutex mutex;
    return mutex;
  }
  std::lock_guard<std::mutex> lock_;
  int saved_ = -1;
};

}  // namespace

std::string OneLineMessage(const std::string& message) {
  std::string line;
  size_t start = 0;
  while (start <= message.size()) {
    size_t end = message.find('\n', start);
    if (end == std::string::npos) end = message.size();
    std::string part = message.substr(start, end - start);
    while (!part.empty() && (part.back() == ' ' || part.back() == '\r')) {
      part.pop_back();
    }
    if (!part.empty()) line += (line.empty() ? "" : "; ") + part;
    start = end + 1;
  }
  return line.empty() ? "unknown error" : line;
}

bool ReadImagePixels(
    const std::string& path,
    const std::function<void(const ImagePixels&)>& check_header,
    ImagePixels* image, std::string* error) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  std::unique_ptr<OIIO::ImageInput> in;
  {
    QuietStderr quiet;
    in = OIIO::ImageInput::open(path, &config);
  }
  if (!in) {
    *error = OneLineMessage(OIIO::geterror());
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  image->width = spec.width;
  image->height = spec.height;
  image->depth = spec.depth;
  image->channels = spec.nchannels;
  image->alpha_channel = spec.alpha_channel;
  if (check_header) check_header(*image);
  image->pixels.resize(static_cast<size_t>(image->width) * image->height *
                       image->channels);
  bool read = false;
  {
    QuietStderr quiet;
    read = in->read_image(0, 0, 0, image->channels, OIIO::TypeDesc::FLOAT,
                          image->pixels.data());
  }
  if (!read) {
    *error = OneLineMessage(in->geterror());
    return false;
  }
  in->close();
  return true;
}

}  // namespace clothfit
