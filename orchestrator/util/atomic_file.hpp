#pragma once
// The one durable writer (after ccache's core/atomicfile.hpp): the text goes to a temporary file in the same
// folder, which is fsynced and renamed over the target, and the folder itself is fsynced so that the rename
// survives a power cut. A reader sees the old content or the new one, never a torn file.
#include <filesystem>
#include <string>

namespace demsa::util {

/// Writes `text` to `path` atomically and durably. Throws IoError naming the file and the system's reason.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

/// The whole content of a file. Throws IoError naming the file when it cannot be read.
std::string read_file(const std::filesystem::path& path);

}  // namespace demsa::util
