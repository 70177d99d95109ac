// The outer layer of a glTF file: reading the bytes and the GLB container (header
// and chunks, checked completely before tinygltf sees them). The first pass over
// the JSON is scene/gltf_json_check.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace lt {

struct GltfContainer {
  bool binary = false;     // .glb
  std::string json_text;   // whole file (.gltf) or the JSON chunk (.glb)
  size_t total_length = 0; // bytes that belong to the file (GLB header length), or of `aligned`
  // A GLB whose chunk lengths are not multiples of 4 (glTF asks for padding; Blender
  // 2.80, older three.js and other writers left it out): a copy with the JSON chunk
  // padded with spaces and the BIN chunk with zeros, for tinygltf, which refuses
  // them; `warning` then says so. Empty for a well-formed file.
  std::vector<unsigned char> aligned;
  // What the loader warns about (without the file name): the padding above, and
  // BIN chunks after the first (ignored); parts joined by "; ".
  std::string warning;
  // Where the BIN chunk's data is in the file's bytes (.glb with a BIN chunk).
  bool has_bin = false;
  size_t bin_offset = 0, bin_length = 0;
};

// Reads a whole file; an lt::InputError naming `file` and the path looked for on failure.
std::vector<unsigned char> ReadFileBytes(const std::filesystem::path& path, const std::string& file);

// Splits a .glb into its chunks, or takes a .gltf as JSON text (told apart by the
// "glTF" magic). Throws lt::InputError for a truncated or inconsistent container;
// chunks not padded to 4 bytes are read as their lengths say (`aligned`).
GltfContainer ParseGltfContainer(const std::vector<unsigned char>& bytes, const std::string& file);

// Makes `json` the container's JSON (a .gltf's text, or a .glb's JSON chunk, the GLB
// rebuilt in `aligned` around the BIN chunk of `bytes`, the file it was parsed from):
// CheckGltfJson's rewrite of integers written as decimals, for tinygltf.
void ReplaceGltfJson(GltfContainer* c, const std::vector<unsigned char>& bytes, std::string json);

// Cuts every data: URI quoted in a message to its first `keep` characters plus
// "..." (a message must not carry megabytes of base64).
std::string ShortenDataUris(const std::string& text, size_t keep = 40);

}  // namespace lt
