#pragma once
// Helpers shared by the pipeline's writers (JSON, SVG, PLY, DOT).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string_view>

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"

namespace maxslice::pipeline::detail {

/// A vector as a JSON array [x, y, z].
[[nodiscard]] inline nlohmann::ordered_json vec_json(const core::Vec3d& v) {
    return nlohmann::ordered_json::array({v.x, v.y, v.z});
}

/// Writes text to a file (binary, replacing it); errors (kIo) name the file.
[[nodiscard]] core::Result<void> write_text(const std::filesystem::path& file,
                                            std::string_view text);

}  // namespace maxslice::pipeline::detail
