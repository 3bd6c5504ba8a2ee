// Runs the ultrafusion executable (UF_EXECUTABLE) as a user would, capturing exit code and output.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace uf::test {

struct CommandResult {
  int code;
  std::string output;  // stdout and stderr together
};

// `prefix` goes before the command: environment assignments ("VAR=value ...") or "cd DIR &&".
inline CommandResult Ultrafusion(const std::string& arguments, bool merge_stderr = true,
                                 const std::string& prefix = "") {
  const std::string command = prefix + (prefix.empty() ? "" : " ") + std::string(UF_EXECUTABLE) + " " +
                              arguments + (merge_stderr ? " 2>&1" : " 2>/dev/null");
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace uf::test
