// Linearizing encoded integer images before stripe extraction
// (ExtractionOptions::transfer; docs/extraction.md, "Encoded images").
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "pipeline/extraction_options.h"

namespace lt {

// Light, 0..1, of an encoded value 0..1 (the inverse of the encoding curve).
double DecodeTransfer(Transfer transfer, double gamma, double encoded);

// The image (all its channels) with each sample v replaced by
// full * DecodeTransfer(v / full), full = the sample type's maximum (255 or
// 65535), into `out`, through a table of full + 1 entries kept in `table`
// (rebuilt when the transfer, gamma or size changes). Returns a view of `out`.
template <typename T>
ImageView<float> LinearizeImage(const ImageView<T>& image, Transfer transfer, double gamma,
                                std::vector<float>* table, std::vector<float>* out);

}  // namespace lt
