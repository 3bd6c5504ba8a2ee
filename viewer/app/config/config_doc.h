// The configuration reference, docs/CONFIG.md, generated from the sections' schemas: every key of every
// section with its default, unit and meaning. `cmake --build build --target config-doc` writes it; a test
// checks that the file in the repository is what this gives.
#pragma once

#include <string>

namespace uf::app {

std::string ConfigReferenceMarkdown();

}  // namespace uf::app
