// Which pixels get the sample budget, and with what first batch
// (FrameRenderer::SampleBudgets).
#include <tbb/parallel_for.h>

#include <cmath>

#include "render/frame_renderer.h"

namespace lt {

Image<uint8_t> FrameRenderer::SampleBudgets(const Image<uint8_t>& reach, bool all_pixels, RenderedFrame* out) const {
  const Camera& cam = scene_.sensor.camera;
  const int w = cam.width(), h = cam.height();
  Image<uint8_t> budget(w, h, 1, all_pixels ? kBeamBudget : kOneSample);
  if (!all_pixels) {
    // The beam's pixels dilated by one pixel plus the largest defocus blur radius
    // seen in the frame; the rest of the glow's pixels.
    double max_coc = 0;
    if (!cam.is_pinhole()) {
      for (float z : out->gt.depth.pixels)
        if (z > 0) max_coc = std::max(max_coc, cam.CircleOfConfusionPx(z));
    }
    const int radius = 1 + int(std::ceil(0.5 * max_coc));
    tbb::parallel_for(0, h, [&](int y) {
      for (int x = 0; x < w; ++x) {
        bool beam = false;
        for (int dy = -radius; dy <= radius && !beam; ++dy) {
          const int yy = y + dy;
          if (yy < 0 || yy >= h) continue;
          for (int dx = -radius; dx <= radius; ++dx) {
            const int xx = x + dx;
            if (xx >= 0 && xx < w && reach.At(xx, yy) == kInBeam) {
              beam = true;
              break;
            }
          }
        }
        budget.At(x, y) = beam ? kBeamBudget : reach.At(x, y) == kInGlow ? kGlowBudget : kOneSample;
      }
    });
  }
  out->near_mask = Image<float>(w, h, 1, 0.0f);
  for (size_t i = 0; i < budget.pixels.size(); ++i) out->near_mask.pixels[i] = budget.pixels[i] != kOneSample;
  return budget;
}

}  // namespace lt
