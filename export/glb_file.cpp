#include "export/glb_file.h"

#include "odometry/io/atomic_file.h"

namespace uf::exporting {

Status WriteSingleNodeGlb(tinygltf::Model& model, tinygltf::Node node, const std::string& path,
                          std::uint64_t* bytes) {
  model.nodes.push_back(std::move(node));
  tinygltf::Scene scene;
  scene.nodes = {static_cast<int>(model.nodes.size()) - 1};
  model.scenes.push_back(scene);
  model.defaultScene = static_cast<int>(model.scenes.size()) - 1;

  AtomicFileWriter file(path);
  if (Status s = file.status(); !s.ok()) return s;
  tinygltf::TinyGLTF writer;
  writer.WriteGltfSceneToStream(&model, file.stream(), false, true);
  if (bytes) *bytes = static_cast<std::uint64_t>(file.stream().tellp());
  return file.Commit();
}

}  // namespace uf::exporting
