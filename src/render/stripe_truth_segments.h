// Stripe centres from the geometry, for ComputeStripeCenters (render/stripe_truth.h).
//
// The pixel-centre search starts from the chief rays of the pixel centres: a
// surface that no pixel centre sees and that lies wholly between two samples on
// one other surface (a thin fin seen nearly edge-on, a sliver of a facet) gives
// it no sign change and no break to search. Here the candidates come from the
// scene's triangles instead: each sheet's plane cuts each triangle in a segment
// (exact, in double, from the corners as the hits are refined: the mesh's float
// vertices through the instance's double transform); the segment is projected
// through the camera model (with its distortion) and its crossings of every
// scan line are found on the segment's parameter. A crossing that is not
// already a centre (within kKnownPx) is decided by real ray casts, as the
// pixel-centre search decides its roots: the chief ray at that exact position
// must see this point first (its triangle, or a point within 1e-3 of a
// pixel's footprint of it), the line is bracketed about it on that surface
// and the root refined by LineScanner::Refine, and the root must be lit
// (LineScanner::Lit: facing camera and projector, in the fan, unshadowed).
// Triangles facing away or outside the fan cost no cast; hidden ones one.
#pragma once

#include <vector>

#include "render/stripe_truth_scanner.h"

namespace lt::stripe_truth_detail {

// A crossing this close (px, along the scan line) to a centre already found on
// its line and plane is that centre.
constexpr double kKnownPx = 1e-4;

// Adds to per_line[line] (sorted by plane, then position along the line) the
// centres whose crossings the geometry gives and no centre within kKnownPx
// holds; lines gaining none are left as they are. Deterministic whatever the
// thread count.
void AddCentresFromSegments(const EmbreeScene& scene, const Camera& camera, const std::vector<WorldSheet>& sheets,
                            const LineScanner& scanner, const Pose& world_from_cam, ScanAxis axis,
                            std::vector<std::vector<StripeCenter>>& per_line);

}  // namespace lt::stripe_truth_detail
