// Stripe-point CSV (pipeline/stripe_csv.h: ReadStripeCsv) and ground-truth
// centres CSV (pipeline/ground_truth.h: ReadTruthCentersCsv), the same bytes as both.
#include "fuzz_common.h"
#include "pipeline/ground_truth.h"
#include "pipeline/stripe_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = lt::fuzz::WriteScratch("points.csv", data, size);
  lt::fuzz::ExpectCleanErrors([&] {
    bool with_plane = false;
    lt::ReadStripeCsv(path, &with_plane);
  });
  lt::fuzz::ExpectCleanErrors([&] { lt::ReadTruthCentersCsv(path); });
  return 0;
}
