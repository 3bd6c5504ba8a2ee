#include "viewer/pipeline/run_folder.h"

#include <unistd.h>

#include <ctime>

namespace uf::pipeline {

namespace fs = std::filesystem;

std::string RunFolderName(std::chrono::system_clock::time_point time) {
  const std::time_t seconds = std::chrono::system_clock::to_time_t(time);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char name[32];
  std::strftime(name, sizeof(name), "%Y%m%d-%H%M%S", &utc);
  return name;
}

Expected<fs::path> CreateVersionedRunFolder(const fs::path& runs_root,
                                            std::chrono::system_clock::time_point time) {
  std::error_code error;
  fs::create_directories(runs_root, error);
  if (error) return Status::Error(runs_root.string() + ": cannot create the folder: " + error.message());
  const std::string name = RunFolderName(time);
  // create_directory is false when the name exists: the next suffix is tried (two runs within a second).
  for (int suffix = 1; suffix < 1000; ++suffix) {
    const fs::path folder = runs_root / (suffix == 1 ? name : name + "-" + std::to_string(suffix));
    if (fs::create_directory(folder, error)) return folder;
    if (error) return Status::Error(folder.string() + ": cannot create the folder: " + error.message());
  }
  return Status::Error(runs_root.string() + ": 999 run folders named " + name + " exist already");
}

Status UpdateLatestLink(const fs::path& runs_root, const fs::path& folder) {
  const fs::path link = runs_root / "latest";
  const fs::path temporary = runs_root / (".latest.tmp" + std::to_string(getpid()));
  std::error_code error;
  fs::remove(temporary, error);
  fs::create_directory_symlink(folder.filename(), temporary, error);
  if (error) return Status::Error(temporary.string() + ": cannot create the link: " + error.message());
  // rename(2) replaces the old link in one step.
  fs::rename(temporary, link, error);
  if (error) {
    const std::string why = error.message();
    fs::remove(temporary, error);
    return Status::Error(link.string() + ": cannot replace the link: " + why);
  }
  return {};
}

}  // namespace uf::pipeline
