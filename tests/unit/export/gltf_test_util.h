// Reading back the .glb files the export tests write: through tinygltf, and through the Khronos glTF
// validator (node + the npm package scripts/setup-test-tools installs; UF_EXPORT_TEST_DIR holds
// validate_gltf.js).
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tiny_gltf.h>

#include <array>
#include <cstdio>
#include <cstdlib>
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

inline std::filesystem::path ValidatorModule() {
  const char* tools = std::getenv("UF_NPM_TOOLS");
  const char* home = std::getenv("HOME");
  const std::filesystem::path root =
      tools ? tools : std::filesystem::path(home ? home : "/") / ".cache/ultrafusion/npm";
  return root / "node_modules" / "gltf-validator";
}

// Why the validator cannot run here (no node, or the package missing), or "" when it can.
inline std::string ValidatorUnavailable() {
  if (std::system("node --version > /dev/null 2>&1") != 0)
    return "node not found: the Khronos glTF validator cannot run";
  if (!std::filesystem::exists(ValidatorModule() / "package.json"))
    return "glTF validator not installed at " + ValidatorModule().string() + ": run scripts/setup-test-tools";
  return "";
}

// Runs the validator; returns its exit status and appends its output to `log`.
inline int Validate(const std::filesystem::path& glb, std::string& log) {
  const std::string command = "node '" UF_EXPORT_TEST_DIR "/validate_gltf.js' '" +
                              ValidatorModule().string() + "' '" + glb.string() + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 512> line;
  while (fgets(line.data(), line.size(), pipe)) log += line.data();
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace uf::exporting::test
