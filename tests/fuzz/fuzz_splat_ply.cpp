// Fuzz target of the 3DGS splat PLY reader: any bytes, read as a .ply file, give a valid model or an error;
// never a crash, a hang, an out-of-bounds access or an allocation far beyond the file's size. A model that
// is returned must pass GaussianModel::Validate and cannot hold more Gaussians than the file has bytes.
#include "export/splat_ply.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = uf::fuzz::WriteInputFile(".ply", data, size);
  std::vector<std::string> ignored;
  const uf::Expected<uf::splat::GaussianModel> model = uf::exporting::ReadSplatPly(path.string(), &ignored);
  if (model.ok() && (!model->Validate().ok() || model->size() > size)) __builtin_trap();
  return 0;
}
