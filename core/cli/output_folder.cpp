#include "output_folder.hpp"

#include "sphforge/errors.hpp"

namespace sphforge::cli {

namespace fs = std::filesystem;

std::filesystem::path choose_output_folder(const std::string& out, bool force, const fs::path& default_folder) {
  auto occupied = [](const fs::path& p) {
    std::error_code ec;
    return fs::exists(p, ec) && !(fs::is_directory(p, ec) && fs::is_empty(p, ec));
  };
  if (!out.empty()) {
    const fs::path folder(out);
    std::error_code ec;
    if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
      throw InputError(out, "", "--out names a file, not a folder");
    if (occupied(folder) && !force)
      throw InputError(out, "", "output folder exists and is not empty; choose another --out or add --force "
                                "to overwrite the files sphforge writes there (nothing is deleted)");
    return folder;
  }
  if (!occupied(default_folder) || force) return default_folder;
  for (int k = 2;; ++k) {
    const fs::path candidate = default_folder.string() + "-" + std::to_string(k);
    if (!occupied(candidate)) return candidate;
  }
}

}  // namespace sphforge::cli
