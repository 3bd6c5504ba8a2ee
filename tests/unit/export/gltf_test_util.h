// Reading back the .glb files the export tests write, through tinygltf.
#pragma once

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <filesystem>
#include <string>

namespace uf::exporting::test {

inline tinygltf::Model LoadGlb(const std::filesystem::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path.string())) << err;
  return model;
}

}  // namespace uf::exporting::test
