// File names and writing of tg-render's images and AOVs.
#pragma once

#include <string>

#include "RenderOptions.h"
#include "tracegraph/backend/render/Renderer.h"

namespace tg::render_tool {

/// Names the files of one frame: OUT.png for a single frame, OUT_0000.png ... for several;
/// AOVs beside the image as OUT.depth.pfm (OUT_0000.depth.pfm ...).
class FrameNaming {
 public:
  FrameNaming(const std::string& output, bool numbered);
  std::string image(int frame) const;
  std::string aov(int frame, const std::string& name) const;

 private:
  std::string stem(int frame) const;
  std::string base_, extension_;
  bool numbered_;
};

/// Writes the beauty image (PNG, or PFM when the output ends in .pfm) and the selected AOVs.
/// Throws tg::Error naming the file on failure.
void writeFrame(const Frame& frame, const FrameNaming& naming, int index,
                const AovSelection& aovs);

}  // namespace tg::render_tool
