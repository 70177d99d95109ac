#include "pipeline/demosaic.h"

#include <stdexcept>

#include "core/error.h"

namespace lt {

ColorFilter ParseBayerPattern(const std::string& text, const std::string& where) {
  if (text == "none") return ColorFilter::kMono;
  if (auto filter = ParseColorFilter(text)) return *filter;
  throw InputError(where, "unknown Bayer pattern '" + text + "' (expected none, rggb, bggr, grbg or gbrg)");
}

const char* BayerPatternName(ColorFilter filter) {
  return filter == ColorFilter::kMono ? "none" : ColorFilterName(filter);
}

namespace {

// For one position in the 2x2 tile: per colour, the offsets of the 3x3
// neighbourhood (centre included) that have that colour.
struct TileTaps {
  int count[3] = {0, 0, 0};
  int dx[3][9], dy[3][9];
};

}  // namespace

template <typename T>
void DemosaicBilinear(const ImageView<T>& mosaic, ColorFilter filter, int phase_x, int phase_y,
                      std::vector<float>* rgb) {
  if (filter == ColorFilter::kMono) throw std::invalid_argument("DemosaicBilinear: not a Bayer mosaic");
  if (mosaic.channels != 1) throw std::invalid_argument("DemosaicBilinear: a mosaic has one channel");
  const int W = mosaic.width, H = mosaic.height;
  rgb->resize(size_t(W) * H * 3);
  if (W <= 0 || H <= 0) return;
  // taps[ty][tx]: view pixels with (x & 1, y & 1) == (tx, ty).
  TileTaps taps[2][2];
  for (int ty = 0; ty < 2; ++ty) {
    for (int tx = 0; tx < 2; ++tx) {
      TileTaps& t = taps[ty][tx];
      const int own = FilterChannel(filter, (tx + (phase_x & 1)) & 1, (ty + (phase_y & 1)) & 1);
      for (int c = 0; c < 3; ++c) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const bool centre = dx == 0 && dy == 0;
            const int col = FilterChannel(filter, (tx + dx + 2 + (phase_x & 1)) & 1, (ty + dy + 2 + (phase_y & 1)) & 1);
            // The pixel's own colour is its own value; other colours come from the neighbours.
            if (c == own ? centre : (!centre && col == c)) {
              t.dx[c][t.count[c]] = dx;
              t.dy[c][t.count[c]] = dy;
              ++t.count[c];
            }
          }
        }
      }
    }
  }
  for (int y = 0; y < H; ++y) {
    const bool inner_row = y > 0 && y < H - 1;
    float* out = rgb->data() + size_t(y) * W * 3;
    for (int x = 0; x < W; ++x) {
      const TileTaps& t = taps[y & 1][x & 1];
      const bool inner = inner_row && x > 0 && x < W - 1;
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        int n = 0;
        for (int k = 0; k < t.count[c]; ++k) {
          int xx = x + t.dx[c][k], yy = y + t.dy[c][k];
          if (!inner) {
            // Mirrored about the border pixel (-1 -> 1, W -> W - 2): the same
            // colour, and the kernel stays symmetric.
            xx = xx < 0 ? -xx : xx >= W ? 2 * (W - 1) - xx : xx;
            yy = yy < 0 ? -yy : yy >= H ? 2 * (H - 1) - yy : yy;
            // A 1-pixel-wide view has no mirror (-1 -> 1 lies outside it too).
            if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
          }
          sum += double(mosaic.Row(yy)[xx]);
          ++n;
        }
        // A 1-pixel-wide view can lack a colour's neighbours: fall back to the
        // pixel's own value.
        out[size_t(x) * 3 + c] = n > 0 ? float(sum / n) : float(mosaic.Row(y)[x]);
      }
    }
  }
}

template void DemosaicBilinear<uint8_t>(const ImageView<uint8_t>&, ColorFilter, int, int, std::vector<float>*);
template void DemosaicBilinear<uint16_t>(const ImageView<uint16_t>&, ColorFilter, int, int, std::vector<float>*);
template void DemosaicBilinear<float>(const ImageView<float>&, ColorFilter, int, int, std::vector<float>*);

}  // namespace lt
