// Checks of a mesh file's header before assimp reads it. assimp allocates for the counts a header
// declares before it reads them (an OFF header declaring 10^100 faces asks for 61 GB), and its PLY
// parser reads past its buffer on some broken headers.
#pragma once

#include <cstdint>
#include <string>

namespace sgt {

// Throws MeshError naming `path` for a PLY header that breaks the format's grammar, and for an OFF
// or PLY header that declares more vertices and faces than the file's `bytes` can hold (every
// element takes at least one byte). Files of other formats pass. The format is told by the
// extension first, by the content otherwise, as assimp picks its reader.
void checkMeshHeader(const std::string& path, std::uintmax_t bytes);

}  // namespace sgt
