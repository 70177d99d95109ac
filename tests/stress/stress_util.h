// Shared machinery of the numerical stress suite (docs/stress.md): render a
// small frame of an in-memory scene, extract and triangulate its stripe, and
// check every output buffer for NaN and infinity. The closed forms each case
// is checked against are here too: on a planar surface a ground-truth stripe
// centre (u, v) must be where the camera ray through (u, v) meets the laser
// sheet's plane, and that point must lie on the surface's plane.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "../render/render_test_world.h"
#include "pipeline/stripe_extractor.h"
#include "pipeline/triangulation.h"
#include "render/frame_renderer.h"

namespace lt::test {

// LT_STRESS_LONG=1 widens the sweeps and enlarges the images.
inline bool LongStress() {
  const char* v = std::getenv("LT_STRESS_LONG");
  return v != nullptr && std::string(v) == "1";
}

struct StressResult {
  RenderedFrame frame;
  std::vector<Plane> planes;           // laser sheet planes, camera frame
  std::vector<StripePoint> extracted;  // stripe centres found in frame.raw
  std::vector<ScanPoint> scanned;      // the same, triangulated
  TriangulationStats stats;
};

// Sheet planes of every laser of the rig (global plane order), camera frame.
inline std::vector<Plane> RigPlanes(const SensorRig& rig) {
  std::vector<Plane> planes;
  for (const LaserProjector& laser : rig.lasers)
    for (int k = 0; k < laser.sheet_count(); ++k) planes.push_back(laser.SheetPlane(k));
  return planes;
}

// The largest digital number the sensor gives: the ADC's full scale or the
// full well, whichever is reached first.
inline double SaturationDn(const ImageSensor& sensor) {
  return std::min(sensor.max_dn(), sensor.params().full_well_e * sensor.SystemGain() + sensor.params().black_level_dn);
}

// The frame's stripe points (rows searched, or columns when the renderer chose
// columns) with the centre-of-mass method, threshold 3% of the sensor's full
// scale (SaturationDn) above its black level: 75 DN, 60 times the dark noise.
inline StressResult RenderAndScan(const World& world, ExtractionMethod method = ExtractionMethod::kCom,
                                  TriangulationOptions triangulation = {}) {
  StressResult r;
  r.frame = FrameRenderer(world.scene, *world.embree).Render(0);
  const SensorRig& rig = world.scene.sensor;
  r.planes = RigPlanes(rig);
  ExtractionOptions ex;
  ex.method = method;
  ex.axis = r.frame.axis == ScanAxis::kRows ? SearchAxis::kRows : SearchAxis::kCols;
  ex.background = rig.image_sensor.params().black_level_dn;
  ex.threshold = ex.background + 0.03 * (SaturationDn(rig.image_sensor) - ex.background);
  StripeExtractor extractor(ex);
  r.extracted = extractor.Extract(r.frame.raw.View());
  for (StripePoint& p : r.extracted) p.plane = 0;  // one sheet in every stress scene
  Triangulator tri(rig.camera, r.planes, triangulation);
  r.scanned = TriangulatePoints(tri, r.extracted, r.frame.world_from_cam, &r.stats);
  return r;
}

inline bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// No NaN or infinity in any buffer the frame and the pipeline produce; raw
// digital numbers within the ADC's range.
inline void ExpectAllFinite(const StressResult& r, const ImageSensor& sensor) {
  for (uint16_t dn : r.frame.raw.pixels) ASSERT_LE(double(dn), sensor.max_dn());
  for (const Image<float>* img : {&r.frame.radiance, &r.frame.laser_radiance, &r.frame.gt.depth, &r.frame.gt.normal,
                                  &r.frame.gt.instance, &r.frame.gt.material, &r.frame.gt.plane, &r.frame.near_mask})
    for (float v : img->pixels) ASSERT_TRUE(std::isfinite(v));
  for (const StripeCenter& c : r.frame.centers) {
    ASSERT_TRUE(std::isfinite(c.u) && std::isfinite(c.v));
    ASSERT_TRUE(Finite(c.p_cam) && Finite(c.p_world));
  }
  for (const StripePoint& p : r.extracted)
    ASSERT_TRUE(std::isfinite(p.u) && std::isfinite(p.v) && std::isfinite(p.width) && std::isfinite(p.strength));
  for (const ScanPoint& s : r.scanned) {
    if (s.p_in_cam) {
      ASSERT_TRUE(Finite(*s.p_in_cam));
    }
    if (s.p_in_world) {
      ASSERT_TRUE(Finite(*s.p_in_world));
    }
  }
}

// Closed form for a ground-truth centre on a planar surface (camera frame):
// the ray through (u, v) meets the sheet's plane at X; X must be the centre's
// point and lie on the surface (on the plane of one of the surface's
// triangles, as stored: float vertices). Returns the largest of |X - p_cam| and the
// distance of X from the surface, relative to the range |X|.
inline double TruthResidual(const Camera& camera, const Plane& sheet, const std::vector<Plane>& surface_in_cam,
                            const StripeCenter& c) {
  auto ray = camera.Unproject({c.u, c.v});
  if (!ray) return INFINITY;
  auto t = sheet.IntersectRay(Eigen::Vector3d::Zero(), *ray);
  if (!t) return INFINITY;
  Eigen::Vector3d X = *t * *ray;
  double range = X.norm();
  double off_surface = INFINITY;
  for (const Plane& p : surface_in_cam) off_surface = std::min(off_surface, std::abs(p.SignedDistance(X)));
  return std::max((X - c.p_cam).norm(), off_surface) / range;
}

// For every extracted point, the distance in pixels (along the search line) to
// the ground-truth centre of the same search line; lines without a truth
// centre are skipped. Returns the largest, and counts the matched points.
inline double WorstCentreErrorPx(const StressResult& r, int* matched = nullptr) {
  const bool rows = r.frame.axis == ScanAxis::kRows;
  double worst = 0;
  int n = 0;
  for (const StripePoint& p : r.extracted) {
    double best = INFINITY;
    for (const StripeCenter& c : r.frame.centers) {
      if (rows ? std::abs(c.v - p.v) > 0.01 : std::abs(c.u - p.u) > 0.01) continue;
      best = std::min(best, rows ? std::abs(c.u - p.u) : std::abs(c.v - p.v));
    }
    if (std::isinf(best)) continue;
    worst = std::max(worst, best);
    ++n;
  }
  if (matched) *matched = n;
  return worst;
}

}  // namespace lt::test
