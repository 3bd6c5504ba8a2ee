// A main() for the fuzz targets when built without libFuzzer (GCC, AddressSanitizer builds): feeds each
// seed file of the given corpus folders to LLVMFuzzerTestOneInput, then a fixed number of deterministic
// mutations of each (byte flips, truncations, inserted and overwritten runs, length fields set to extremes),
// so the regular sanitizer test run exercises damaged inputs too. Usage: replay MUTATIONS DIR...
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes Mutate(const Bytes& seed, std::mt19937_64& rng) {
  Bytes out = seed;
  auto pick = [&](std::size_t n) {
    return n ? std::uniform_int_distribution<std::size_t>(0, n - 1)(rng) : 0;
  };
  switch (pick(5)) {
    case 0:  // flip a few bits
      for (int i = 0, n = 1 + pick(8); i < n && !out.empty(); ++i) out[pick(out.size())] ^= 1u << pick(8);
      break;
    case 1:  // truncate
      out.resize(pick(out.size() + 1));
      break;
    case 2: {  // insert a run of random bytes
      Bytes run(1 + pick(64));
      for (auto& b : run) b = static_cast<std::uint8_t>(rng());
      out.insert(out.begin() + pick(out.size() + 1), run.begin(), run.end());
      break;
    }
    case 3:  // overwrite four bytes with an extreme 32-bit value (length and count fields)
      if (out.size() >= 4) {
        const std::uint32_t values[] = {0, 1, 0x7fffffff, 0x80000000, 0xffffffff};
        const std::uint32_t v = values[pick(5)];
        std::size_t at = pick(out.size() - 3);
        for (int k = 0; k < 4; ++k) out[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
      }
      break;
    default:  // duplicate a slice
      if (!out.empty()) {
        std::size_t from = pick(out.size()), len = 1 + pick(std::min<std::size_t>(256, out.size() - from));
        Bytes slice(out.begin() + from, out.begin() + from + len);
        out.insert(out.begin() + pick(out.size() + 1), slice.begin(), slice.end());
      }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s MUTATIONS CORPUS_DIR...\n", argv[0]);
    return 2;
  }
  const long mutations = std::strtol(argv[1], nullptr, 10);
  std::mt19937_64 rng(20261121);
  long runs = 0;
  for (int a = 2; a < argc; ++a) {
    for (const auto& entry : std::filesystem::directory_iterator(argv[a])) {
      if (!entry.is_regular_file()) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      const Bytes seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      LLVMFuzzerTestOneInput(seed.data(), seed.size());
      for (long m = 0; m < mutations; ++m, ++runs) {
        const Bytes input = Mutate(seed, rng);
        LLVMFuzzerTestOneInput(input.data(), input.size());
      }
      ++runs;
    }
  }
  std::printf("replayed %ld inputs\n", runs);
  return runs > 0 ? 0 : 1;
}
