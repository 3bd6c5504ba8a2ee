// ExpectConfigError: loading `text` as a configuration file fails, with a message that names the file and
// holds every one of `parts` (the key path, its line, the value).
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/temp_dir.h"
#include "viewer/app/config/config_file.h"

namespace uf::app::test {

inline void ExpectConfigError(const std::string& text, const std::vector<std::string>& parts) {
  testing::TempDir dir;
  const std::string file = dir.Write("bad.yaml", text);
  Expected<ConfigFile> loaded = LoadConfigFile(file);
  ASSERT_FALSE(loaded.ok()) << text;
  EXPECT_NE(loaded.error().find(file), std::string::npos) << loaded.error();
  for (const std::string& part : parts)
    EXPECT_NE(loaded.error().find(part), std::string::npos) << loaded.error();
}

}  // namespace uf::app::test
