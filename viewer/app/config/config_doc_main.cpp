// config_doc [FILE]: writes docs/CONFIG.md (the configuration reference generated from the schemas) to
// FILE, or to stdout.
#include <fstream>
#include <iostream>

#include "viewer/app/config/config_doc.h"

int main(int argc, char** argv) {
  if (argc > 2) {
    std::cerr << "usage: config_doc [FILE]\n";
    return 2;
  }
  if (argc == 1) {
    std::cout << uf::app::ConfigReferenceMarkdown();
    return 0;
  }
  std::ofstream file(argv[1], std::ios::binary);
  file << uf::app::ConfigReferenceMarkdown();
  if (!file.flush()) {
    std::cerr << "config_doc: cannot write " << argv[1] << "\n";
    return 1;
  }
  return 0;
}
