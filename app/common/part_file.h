// The partial result of a split render (raytrace -o NAME.part, read by raymerge and written by
// the MPI mode's workers): a RenderPart with what identifies its render, so parts of different
// scenes or settings are never merged. The format (docs/cluster.md):
//
//   RTPART 1                        text header, one item a line
//   scene HASH                      FNV-1a 64 of every file the scene read, hex
//   settings TEXT                   every setting the image depends on, one line
//   image W H
//   spp N                           samples per pixel of the whole render
//   tile X0 Y0 X1 Y1                pixels [X0, X1) x [Y0, Y1)
//   samples FIRST COUNT             samples [FIRST, FIRST + COUNT) of every pixel
//   rays CAMERA SHADOW REFLECTED REFRACTED
//   blocks K                        then K lines "block START LEVEL" (samples [START, START +
//   2^LEVEL)) data K x (sums, then sums of squares) x 3 doubles per pixel, row-major, little-endian
//   8 bytes: FNV-1a 64 of every byte before them
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rt/render/render.h"
#include "rt/scene/scene_desc.h"

namespace rtapp {

/// What a part belongs to: parts merge only when all of it is equal.
struct PartHeader {
    std::string scene_hash;  // 16 hex digits
    std::string settings;    // one line
    int width = 0, height = 0;
    uint32_t spp = 0;
};

struct PartFile {
    PartHeader header;
    rt::RenderPart part;
};

/// FNV-1a 64 of `data`, continuing from `hash`.
uint64_t fnv1a(const std::string& data, uint64_t hash = 0xcbf29ce484222325ull);

/// The scene's identity: FNV-1a 64 (16 hex digits) of the contents of every file it read (its
/// .ray files, key files and textures, in the description's order) with their names.
std::string scene_hash(const rt::SceneDesc& desc);

/// Writes the part atomically (a temporary name renamed when complete). Throws std::runtime_error.
void write_part(const std::string& path, const PartFile& part);
/// Reads a part; std::runtime_error with what is wrong ("not a part file", "truncated: ...",
/// "corrupt: its checksum does not match", a bad header line) otherwise.
PartFile read_part(const std::string& path);
/// Reads a part's header alone and checks it, and the file's size against the data it
/// announces, as read_part does (but the checksum): its blocks hold no sums. raymerge reads
/// every part's header first, so that parts that do not cover their image are refused before
/// any pixel is read or the image allocated.
PartFile read_part_header(const std::string& path);

/// Checks from the parts' headers alone (their tiles and samples) that they cover every pixel of
/// their image (the first part's width x height) with exactly the samples 0 .. spp - 1, without
/// a buffer of the image's size. Throws std::invalid_argument naming the first pixel, row by
/// row, and the samples in no part or in two (the parts by `names`, or "part K"), as
/// rt::merge_parts does.
void check_coverage(const std::vector<PartFile>& parts, const std::vector<std::string>& names);

}  // namespace rtapp
