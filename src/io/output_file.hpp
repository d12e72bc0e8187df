// Writing files so that no reader, crash or kill ever sees half of one (docs/reliability.md,
// "Output"): the bytes go to a hidden temporary file in the same folder, are flushed to the disk,
// and the temporary file is renamed over the final name, so the file is either the old one whole
// or the new one whole. Errors name the file and the reason ("cannot write out/scene.json: No
// space left on device").
#pragma once

#include <fcntl.h>

#include <filesystem>
#include <stdexcept>
#include <string_view>

namespace linx::io {

/// "cannot WHAT PATH: the reason of errno `error`".
std::runtime_error ioError(std::string_view what, const std::filesystem::path& path, int error);

/// Writes all of `data` to the descriptor `fd` (write(2) may write less than asked, or be
/// interrupted); a failure throws ioError("write", shown, errno).
void writeAll(int fd, std::string_view data, const std::filesystem::path& shown);

/// Writes `data` as the file `path` atomically (above). With `dir_fd` a descriptor of a folder,
/// `path` is a plain name inside it and `shown` is how messages name the file; with AT_FDCWD,
/// `path` is a path as usual. A link in place of the temporary file is never followed.
void writeFileAtomically(const std::filesystem::path& path, std::string_view data,
                         int dir_fd = AT_FDCWD, const std::filesystem::path& shown = {});

}  // namespace linx::io
