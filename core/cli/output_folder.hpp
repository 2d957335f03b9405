// The output folder of `sphforge run` and `sphforge bench`: the one rule both follow.
#pragma once

#include <filesystem>
#include <string>

namespace sphforge::cli {

/// An explicit `out` (non-empty) that exists and is not empty is refused without `force` (and even
/// then nothing is deleted: files are only overwritten); one that names a file is refused. Without
/// `out`, `default_folder` is used, or, when it is occupied and `force` is not given, the first free
/// `default_folder-N` (N = 2, 3, ...), so an earlier run is never touched. Throws InputError.
std::filesystem::path choose_output_folder(const std::string& out, bool force,
                                           const std::filesystem::path& default_folder);

}  // namespace sphforge::cli
