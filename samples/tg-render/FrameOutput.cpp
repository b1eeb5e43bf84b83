#include "FrameOutput.h"

#include <cstdio>
#include <filesystem>

#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/render/ImageIO.h"

namespace tg::render_tool {

FrameNaming::FrameNaming(const std::string& output, bool numbered) : numbered_(numbered) {
  const std::filesystem::path p(output);
  extension_ = p.extension().string();
  if (extension_.empty()) extension_ = ".png";
  base_ = (p.parent_path() / p.stem()).string();
}

std::string FrameNaming::stem(int frame) const {
  if (!numbered_) return base_;
  char digits[16];
  std::snprintf(digits, sizeof digits, "_%04d", frame);
  return base_ + digits;
}

std::string FrameNaming::image(int frame) const { return stem(frame) + extension_; }

std::string FrameNaming::aov(int frame, const std::string& name) const {
  return stem(frame) + "." + name + ".pfm";
}

void writeFrame(const Frame& frame, const FrameNaming& naming, int index,
                const AovSelection& aovs) {
  const std::string image = naming.image(index);
  const std::filesystem::path parent = std::filesystem::path(image).parent_path();
  if (!parent.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
    if (ec) throw Error(image + ": cannot create folder " + parent.string() + ": " + ec.message());
  }
  if (std::filesystem::path(image).extension() == ".pfm")
    writePfm(frame.beauty, image);
  else
    writePng(frame.beauty, image);
  if (aovs.depth) writePfm(frame.depth, naming.aov(index, "depth"));
  if (aovs.normal) writePfm(frame.normal, naming.aov(index, "normal"));
  if (aovs.instance) writeIdPfm(frame.instanceId, naming.aov(index, "instance"));
  if (aovs.prim) writeIdPfm(frame.primId, naming.aov(index, "prim"));
}

}  // namespace tg::render_tool
