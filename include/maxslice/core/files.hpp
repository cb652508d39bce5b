#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/core/result.hpp"

namespace maxslice::core {

/// Refuses, before anything opens it, a path that is not a regular file: a FIFO (which would
/// block the reader forever), a device, a socket, a directory or a missing file. `what` names
/// the input in the message ("part file", "profile", "program").
[[nodiscard]] Result<void> check_input_file(const std::filesystem::path& path,
                                            std::string_view what);

/// Whether write_file_atomic waits until the bytes are on the disk before the rename (a
/// program: a power cut then leaves the old file or the new one), or leaves that to the
/// system (previews, hundreds of small files: a wait for each costs seconds).
enum class Durability : unsigned char { kSynced, kFlushed };

/// Writes `bytes` to `path` so that nothing a user had is lost: into a temporary file beside
/// the target, written and closed with every error checked (and with kSynced, on the disk),
/// then renamed over the target (a link is followed: the file it names is replaced). On
/// failure the previous file (if any) is left as it was, the temporary file is removed, and
/// the error names the cause (the system's errno text). An empty path or a folder is
/// refused; "-" is standard output; a device or a pipe (/dev/stdout, a FIFO) is written
/// straight into.
[[nodiscard]] Result<void> write_file_atomic(const std::filesystem::path& path,
                                             std::string_view bytes,
                                             Durability durability = Durability::kSynced);

/// Writes all of `bytes` to standard output and flushes it; an error (a full disk, a closed
/// pipe) names its cause.
[[nodiscard]] Result<void> write_stdout(std::string_view bytes);

/// Refuses an output path that names one of the inputs (the same file, by device and inode
/// when both exist, else by their absolute, normalised paths), before any work is done.
/// `option` names the output's flag in the message ("-o", "--json").
[[nodiscard]] Result<void> check_output_not_input(const std::filesystem::path& output,
                                                  std::string_view option,
                                                  const std::vector<std::filesystem::path>& inputs);

/// One readable line for a message: control and non-ASCII bytes are written as \xNN
/// (so a file's bytes cannot drive the terminal), and text longer than `max_chars` is cut
/// with "... (N more bytes)".
[[nodiscard]] std::string printable(std::string_view text, std::size_t max_chars = 160);

}  // namespace maxslice::core
