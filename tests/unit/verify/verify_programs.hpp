#pragma once
// Programs written by hand for the verifier tests, line by line, without the writers: a
// zigzag block with correct layers and the blocks that plant faults into it.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

#include "maxslice/machine/profile.hpp"
#include "maxslice/verify/replay.hpp"
#include "maxslice/verify/verify.hpp"
#include "support/fixtures.hpp"

namespace maxslice::verify::testing {

inline machine::Profiles load(const std::string& name) {
    const std::filesystem::path file =
        std::filesystem::path(MAXSLICE_SOURCE_DIR) / "examples" / "profiles" / name;
    auto f = machine::read_profile(file);
    if (!f || !f->machine || !f->process) return {};
    return {*f->machine, *f->process};
}

/// Writes program lines in gm, linuxcnc, fanuc or siemens, with the profile's laser codes.
class ProgramText {
public:
    ProgramText(const machine::Profiles& p, ProgramDialect d, bool rotary)
        : p_(p), d_(d), rotary_(rotary) {
        switch (d_) {
            case ProgramDialect::kGm:
                line("G21");
                line("G90");
                break;
            case ProgramDialect::kLinuxCnc:
                line("(hand-written test program)");
                line("G21 G90 G94 G17");
                break;
            case ProgramDialect::kFanuc:
                line("%");
                line("O1000 (TEST)");
                line("G21 G90 G94 G17");
                break;
            case ProgramDialect::kSiemens:
                line("; test");
                line("G71 G90 G94 G17");
                break;
        }
    }

    /// Every later move adds `offset` to X Y Z and, unless given, writes these rotary values
    /// (a tool-centre-point program: X Y Z = pivot + tip).
    void set_frame(const core::Vec3d& offset, double a, double c) {
        offset_ = offset;
        a_ = a;
        c_ = c;
    }

    /// A G1 block; returns its line number.
    int move(double x, double y, double z, double feed, std::optional<double> a = std::nullopt,
             std::optional<double> c = std::nullopt) {
        std::string b =
            fmt::format("G1 X{:.3f} Y{:.3f} Z{:.3f}", x + offset_.x, y + offset_.y, z + offset_.z);
        if (rotary_) b += fmt::format(" A{:.3f} C{:.3f}", a.value_or(a_), c.value_or(c_));
        b += fmt::format(" F{:.1f}", feed);
        return line(b);
    }
    int laser(bool on) {
        const auto& codes = p_.machine.codes;
        const double w = on ? p_.process.laser_power_w : p_.process.laser_power_off_w;
        const double g = on ? p_.process.powder_feed_g_min : 0.0;
        on_ = on;
        int n = lines_;
        const std::array<const machine::CodeTemplate*, 2> order =
            on ? std::array{&codes.powder_on, &codes.laser_on}
               : std::array{&codes.laser_off, &codes.powder_off};
        for (const auto* t : order) {
            for (const auto& b : t->blocks) {
                n = line(machine::expand_block(b, w, g, p_.machine.laser_power_max_w));
            }
        }
        return n;
    }
    int raw(const std::string& block) { return line(block); }
    [[nodiscard]] const std::string& text() const { return out_; }
    [[nodiscard]] int lines() const { return lines_; }

private:
    int line(const std::string& block) {
        if (d_ == ProgramDialect::kGm) {
            out_ += on_ ? fmt::format("{:.2f} {:.2f} ", p_.process.laser_power_w,
                                      p_.process.powder_feed_g_min)
                        : "0.00 0.00 ";
        }
        out_ += block;
        out_ += '\n';
        return ++lines_;
    }

    const machine::Profiles& p_;
    ProgramDialect d_;
    bool rotary_;
    core::Vec3d offset_{};
    double a_ = 0.0;
    double c_ = 0.0;
    bool on_ = false;
    int lines_ = 0;
    std::string out_;
};

/// A square block [cx - half, cx + half] x [cy - half, cy + half] x [0, layers * h] built by a
/// zigzag of tracks along X, pitch track x (1 - overlap) rounded so that the outer tracks touch
/// the sides, one wire per layer, travelling back over the block between layers.
inline double zigzag_block(ProgramText& prog, const machine::Profiles& p, double cx, double cy,
                           double half, int layers) {
    const double w = p.process.track_width_mm;
    const double h = p.process.layer_height_mm;
    const double feed = p.process.deposition_feed_mm_min;
    const double travel = p.process.travel_feed_mm_min;
    const double span = 2.0 * half - w;
    const int tracks = static_cast<int>(std::ceil(span / (w * (1.0 - p.process.overlap)))) + 1;
    const double pitch = span / (tracks - 1);
    const double x0 = cx - half + 0.5 * w, x1 = cx + half - 0.5 * w;
    const double y0 = cy - half + 0.5 * w;
    double length = 0.0;
    for (int k = 1; k <= layers; ++k) {
        const double z = k * h;
        prog.move(x0, y0, z, travel);
        prog.laser(true);
        for (int i = 0; i < tracks; ++i) {
            const double y = y0 + i * pitch;
            prog.move(i % 2 == 0 ? x1 : x0, y, z, feed);
            length += x1 - x0;
            if (i + 1 < tracks) {
                prog.move(i % 2 == 0 ? x1 : x0, y + pitch, z, feed);
                length += pitch;
            }
        }
        prog.laser(false);
    }
    return length;
}

/// The block the tests' programs build: 30 x 30 mm, 12 layers of 0.5 mm.
inline constexpr double kHalf = 15.0;
inline constexpr int kLayers = 12;

/// A model placed on the plate as the job places a part standing along +Z.
inline mesh::TriangleMesh placed(const machine::Profiles& p, mesh::TriangleMesh m) {
    auto r = place_model(std::move(m), {0, 0, 1}, p.machine);
    EXPECT_TRUE(r.has_value());
    return r.value_or(mesh::TriangleMesh{});
}

/// The block (kHalf, kLayers), placed.
inline mesh::TriangleMesh placed_block(const machine::Profiles& p) {
    return placed(p, test::box({0, 0, 0}, {2 * kHalf, 2 * kHalf, kLayers * 0.5}));
}

}  // namespace maxslice::verify::testing
