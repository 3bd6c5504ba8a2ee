// Finishing a glTF model as a .glb file: the one node as the default scene, written atomically (temporary
// name, then rename). Internal to uf_export (tinygltf stays out of the public headers).
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <string>

#include "odometry/types/status.h"

namespace uf::exporting {

// Adds `node` as the only node of the model's default scene and writes the model to `path`; `bytes`
// receives the file size.
Status WriteSingleNodeGlb(tinygltf::Model& model, tinygltf::Node node, const std::string& path,
                          std::uint64_t* bytes = nullptr);

}  // namespace uf::exporting
