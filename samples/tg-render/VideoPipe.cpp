#include "VideoPipe.h"

#include <cstdlib>
#include <vector>

#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/render/ImageIO.h"

namespace tg::render_tool {
namespace {

bool ffmpegAvailable() { return std::system("command -v ffmpeg > /dev/null 2>&1") == 0; }

std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

VideoPipe::VideoPipe(const std::string& path, std::uint32_t width, std::uint32_t height,
                     double fps)
    : path_(path) {
  if (!ffmpegAvailable())
    throw Error("--video " + path + ": ffmpeg is not installed (apt-get install ffmpeg); " +
                "the frames are still written as images");
  const std::string command = "ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgb24 -s " +
                              std::to_string(width) + "x" + std::to_string(height) +
                              " -r " + std::to_string(fps) +
                              " -i - -pix_fmt yuv420p -vf pad=ceil(iw/2)*2:ceil(ih/2)*2 " +
                              shellQuote(path);
  pipe_ = popen(command.c_str(), "w");
  if (!pipe_) throw Error("--video " + path + ": cannot start ffmpeg");
}

VideoPipe::~VideoPipe() {
  if (pipe_) pclose(pipe_);
}

void VideoPipe::write(const Image& beauty) {
  std::vector<unsigned char> rgb(static_cast<std::size_t>(beauty.width()) * beauty.height() * 3);
  std::size_t k = 0;
  for (std::uint32_t y = 0; y < beauty.height(); ++y)
    for (std::uint32_t x = 0; x < beauty.width(); ++x)
      for (std::uint32_t c = 0; c < 3; ++c) {
        const float v = srgbEncode(beauty.at(x, y, c));
        const float clamped = v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
        rgb[k++] = static_cast<unsigned char>(clamped * 255.0f + 0.5f);
      }
  if (std::fwrite(rgb.data(), 1, rgb.size(), pipe_) != rgb.size())
    throw Error("--video " + path_ + ": ffmpeg stopped reading frames");
}

void VideoPipe::finish() {
  if (!pipe_) return;
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  if (status != 0) throw Error("--video " + path_ + ": ffmpeg failed");
}

}  // namespace tg::render_tool
