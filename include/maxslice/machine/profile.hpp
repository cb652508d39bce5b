#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maxslice/core/result.hpp"
#include "maxslice/core/vec3.hpp"

namespace maxslice::machine {

/// One measured point of the speed law: a single track laid at this feed is this high.
struct SpeedPoint {
    double feed_mm_min = 0.0;
    double height_mm = 0.0;
};

/// The deposition process (METHOD.md, reference process): what the bead needs, independent of
/// the machine that lays it. Lengths in mm, feeds in mm/min, powder in g/min, power in W.
/// TOML keys are the member names (table `[process]`); see docs/profiles.md.
struct ProcessProfile {
    double track_width_mm = 2.5;             ///< bead width, (0, 50]
    double layer_height_mm = 0.5;            ///< nominal layer height, in [h_min, h_max]
    double h_min_mm = 0.3;                   ///< thinnest layer (adaptive / wedge layers)
    double h_max_mm = 0.7;                   ///< thickest layer
    double overlap = 0.3;                    ///< share of a track the next one covers, [0, 1)
    int contour_passes = 1;                  ///< passes along the wires before the fill, >= 0
    double laser_power_w = 700.0;            ///< while depositing, > 0
    double laser_power_off_w = 0.0;          ///< written while the laser is off, < laser_power_w
    double powder_feed_g_min = 8.0;          ///< while depositing (0 = no powder, e.g. dry run)
    double deposition_feed_mm_min = 381.0;   ///< nominal feed with the laser on
    double travel_feed_mm_min = 2540.0;      ///< feed of idle moves (laser off)
    double dwell_after_laser_on_ms = 0.0;    ///< wait after switching on, for the powder stream
    double self_supporting_angle_deg = 0.0;  ///< slope the process holds by itself, [0, 90)
    /// Height above the plate within which the part's footprint is built straight up (a pad
    /// machined off with the plate; decision 0017), [0, 50]; 0 = off.
    double footing_mm = 1.0;
    /// Bodies that touch neither the rest of the part nor the plate are left out of the plan
    /// with a warning (decision 0036); false keeps them, and the job refuses the part.
    bool leave_out_free_bodies = true;
    /// The near-net shape (decision 0025): the part file is the finished part, and the job
    /// deposits it grown by this machining allowance per side, [0, 20]; 0 = off.
    double machining_stock_mm = 0.0;
    /// Holes, slots and inside corners narrower than this (mm) are filled and machined after
    /// the build, [0, 100]; 0 = off. Both belong to the part: `[[process.finer]]` entries
    /// inherit them from [process] and cannot set their own.
    double fill_below_mm = 0.0;
    /// Share of the delivered powder that ends up in the bead, (0, 1]; unset = unknown, and
    /// the summary then reports only the powder delivered.
    std::optional<double> powder_catch_efficiency;
    /// `speed_height`: measured (feed, track height) pairs, feeds increasing and heights
    /// decreasing (METHOD.md section 10); empty = the constant-mass law through the nominal
    /// point (machine/speed_law.hpp).
    std::vector<SpeedPoint> speed_height;
    /// `[[process.finer]]`: whole processes with narrower tracks (another head, or a zoom
    /// optic), each track narrower than the one before; a program job falls back to them in
    /// order when this process leaves the part under the coverage target or lays no track
    /// (docs/decisions/0019). Each is read and checked like [process]; they hold no `finer`.
    std::vector<ProcessProfile> finer;
};

/// How machine axes follow from part coordinates (METHOD.md section 11). The head is fixed and
/// vertical; on the table-tilt machines the table turns the part. See machine/kinematics.hpp.
enum class Kinematics {
    kXyz,      ///< "xyz": Cartesian X, Y, Z; the tool direction is always +Z
    kTableAc,  ///< "xyzac-trt": A tilts the table about X, then C turns it about Z on the tilt
    kTableBc,  ///< "xyzbc-trt": B tilts the table about Y, then C turns it about Z on the tilt
};

/// Output dialect of the program writer.
enum class Dialect {
    kGm,        ///< the reference lab's format: power and powder columns, then a G-code block
    kLinuxCnc,  ///< RS-274 as LinuxCNC's interpreter reads it (joint space on table machines)
    kFanuc,     ///< Fanuc-style RS-274, tool centre point control (G43.4) on table machines
    kSiemens,   ///< Siemens Sinumerik, TRAORI on table machines
};

/// Travel limits of one axis in program coordinates: mm for X, Y, Z, degrees for A, B, C.
struct AxisLimits {
    std::string name;  ///< "X", "Y", "Z", "A", "B", "C"
    double min = 0.0;
    double max = 0.0;
};

/// An M-code (or any block) template: one or more blocks, one output line each. Placeholders
/// `{power}` (W), `{power_pct}` (percent of the machine's laser_power_max_w) and `{powder}`
/// (g/min) are replaced by the value with 2 decimals. No blocks = nothing is written.
struct CodeTemplate {
    std::vector<std::string> blocks;
};

/// The blocks a machine uses to switch laser and powder, and optional extra blocks written
/// after the header and before the program end.
struct MachineCodes {
    CodeTemplate laser_on;
    CodeTemplate laser_off;
    CodeTemplate powder_on;
    CodeTemplate powder_off;
    CodeTemplate program_start;
    CodeTemplate program_end;
};

/// The deposition head as the collision check sees it (METHOD.md section 7): a cone with its
/// apex at the melt pool (the powder stream and nozzle), axis along the build direction, and
/// optionally a cylinder for the head body above it. TOML table [machine.nozzle].
struct NozzleProfile {
    double half_angle_deg = 30.0;  ///< theta/2, in (0, 85]
    double cone_length_mm = 40.0;  ///< H, > 0 and <= 1000
    double standoff_mm = 10.0;     ///< melt pool to nozzle tip, in (0, cone_length_mm]
    double body_radius_mm = 0.0;   ///< head body cylinder above the cone, >= 0 (0 = none)
    double body_length_mm = 0.0;   ///< >= 0; > 0 when body_radius_mm > 0 and vice versa
    double clearance_mm = 1.0;     ///< smallest accepted gap to deposited material, in [0, 50]
};

/// The substrate plate the part is built on, TOML table [machine.substrate]: a box fixed to
/// the table, its top face the plate (part z = 0), centred on plate_center(), the part's
/// place. The head must not meet it; beads rest on it only within its top face.
struct SubstrateProfile {
    double size_x_mm = 0.0;     ///< along the part frame's X, > 0
    double size_y_mm = 0.0;     ///< along Y, > 0
    double thickness_mm = 0.0;  ///< below the plate, > 0
};

/// The geometry of a tilting-rotary table, TOML table [machine.table] (docs/profiles.md).
/// Machine coordinates are the program's X, Y, Z (the tool tip, mm). The part frame is fixed
/// to the table; with every rotary axis at 0 it is the machine frame moved to `pivot`: a part
/// point q sits at the machine point pivot + q. The tilt axis (A along +X, or B along +Y)
/// passes through `pivot`; the C axis, carried by the tilt, is parallel to +Z at rotary zero
/// and passes through pivot + (c_offset_x_mm, c_offset_y_mm, 0).
struct TableProfile {
    core::Vec3d pivot_mm;        ///< `pivot`, a point of the tilt axis, machine coordinates
    double c_offset_x_mm = 0.0;  ///< `c_offset[0]`: the C axis from the pivot along X, mm
    double c_offset_y_mm = 0.0;  ///< `c_offset[1]`: the C axis from the pivot along Y, mm
    /// `a_direction` (xyzac-trt) or `b_direction` (xyzbc-trt): +1 when a positive tilt angle
    /// turns the table (and the part) by the right-hand rule about +X (+Y); -1 the other way.
    int tilt_direction = 1;
    /// `c_direction`: +1 when a positive C turns the table by the right-hand rule about the
    /// table's +Z; -1 the other way.
    int c_direction = 1;
    double retract_mm = 10.0;  ///< `retract_mm`: lift along the tool axis before a rotation, > 0
};

/// A machine: kinematics, axis limits, accepted feed and power ranges, dialect and codes.
/// TOML table `[machine]`; see docs/profiles.md.
struct MachineProfile {
    std::string name;
    Kinematics kinematics = Kinematics::kXyz;
    Dialect dialect = Dialect::kGm;
    /// X, Y, Z in that order for kXyz; X, Y, Z, A, C for kTableAc; X, Y, Z, B, C for kTableBc.
    std::vector<AxisLimits> axes;
    double feed_min_mm_min = 1.0;         ///< slowest feed the machine accepts, > 0
    double feed_max_mm_min = 10000.0;     ///< fastest feed, >= feed_min
    double laser_power_min_w = 0.0;       ///< lowest power when on (0 W = off is always fine)
    double laser_power_max_w = 1000.0;    ///< highest power, > 0
    double powder_feed_max_g_min = 50.0;  ///< highest powder feed, >= 0
    MachineCodes codes;
    /// The head for the collision check; unset = no [machine.nozzle] table, and the planner
    /// then uses NozzleProfile's defaults and says so.
    std::optional<NozzleProfile> nozzle;
    /// The substrate plate; unset = no [machine.substrate] table: the head is checked against
    /// deposited material only and every bead at the plate's height rests on the plate.
    std::optional<SubstrateProfile> substrate;
    /// The table of kTableAc / kTableBc (required there, refused for kXyz).
    std::optional<TableProfile> table;

    /// The limits of the named axis, or nullptr when the machine has no such axis.
    [[nodiscard]] const AxisLimits* find_axis(std::string_view axis_name) const;
};

/// What one profile file holds: a `[machine]` table, a `[process]` table, or both.
struct ProfileFile {
    std::optional<MachineProfile> machine;
    std::optional<ProcessProfile> process;
};

/// A complete, cross-checked pair.
struct Profiles {
    MachineProfile machine;
    ProcessProfile process;
};

/// The profiles with `process.finer[n - 1]` as the process (n >= 1; n = 0 gives them
/// unchanged); the result holds no finer processes. kInvalidInput when there is no such one.
[[nodiscard]] core::Result<Profiles> with_finer_process(const Profiles& profiles, int n);

/// Checks every range and cross-check of a process profile (h_min <= layer <= h_max, layer
/// <= track width, 0 <= overlap < 1, positive widths and feeds ...). Errors (kInvalidInput)
/// name the key as in the TOML file ("process.track_width_mm"), the value and the range.
[[nodiscard]] core::Result<void> validate(const ProcessProfile& process);

/// Checks a machine profile: the kinematics' axes present in order with min < max, ranges,
/// templates (known placeholders only, one line per block, no motion: motion_word), the nozzle when
/// given (ranges, standoff_mm <= cone_length_mm, body radius and length both 0 or both > 0), the
/// table present exactly for the table-tilt kinematics, with its ranges. Errors name the key
/// ("machine.axes.X.min", "machine.nozzle.half_angle_deg", "machine.table.pivot").
[[nodiscard]] core::Result<void> validate(const MachineProfile& machine);

/// Checks that a machine can run a process: the process's feeds, laser power and powder feed
/// lie in the machine's ranges. Errors name both keys.
[[nodiscard]] core::Result<void> check_compatible(const MachineProfile& machine,
                                                  const ProcessProfile& process);

/// Parses profile TOML text (`source` names it in errors). Each present table is read
/// completely and validated: missing keys, unknown keys (with a suggestion for a likely
/// typo), wrong types and out-of-range values are refused, naming the key. A file with
/// neither table is refused. Errors: kInvalidInput with context "profile SOURCE".
[[nodiscard]] core::Result<ProfileFile> parse_profile(std::string_view toml_text,
                                                      std::string_view source);

/// Reads and parses one profile file (kIo when it cannot be read).
[[nodiscard]] core::Result<ProfileFile> read_profile(const std::filesystem::path& file);

/// Reads one file holding both tables, or several files that together hold each table exactly
/// once (e.g. a machine file and a process file), and checks the pair is compatible.
[[nodiscard]] core::Result<Profiles> load_profiles(std::span<const std::filesystem::path> files);

/// "gm" / "linuxcnc" / "fanuc" / "siemens", as in the profile.
[[nodiscard]] std::string_view dialect_name(Dialect dialect);

/// The dialect of a profile's (or the CLI's) name: "gm", "linuxcnc", "fanuc", "siemens";
/// nullopt for any other text (case-sensitive).
[[nodiscard]] std::optional<Dialect> parse_dialect(std::string_view name);

/// "xyz" / "xyzac-trt" / "xyzbc-trt", as in the profile.
[[nodiscard]] std::string_view kinematics_name(Kinematics kinematics);

/// Where a part stands on the plate, part coordinates (Z = 0): the middle of the X and Y
/// travel of an "xyz" machine, the C axis (table c_offset) of a table-tilt machine
/// (docs/program-dialects.md).
[[nodiscard]] core::Vec3d plate_center(const MachineProfile& machine);

/// True for the tilting-rotary table kinematics (kTableAc, kTableBc).
[[nodiscard]] bool is_table_tilt(Kinematics kinematics);

/// The first word of a `[machine.codes]` block that would move the machine, or nullopt: a
/// motion G code (G0-G3, G5.x, G28, G30, G33.x, G38.x, canned cycles G73-G89 but G80) or an
/// axis word (X Y Z A B C U V W I J K), read as RS-274 and Sinumerik read a block: case
/// folded, comments `( )` and `;` left out, placeholders standing for numbers, `$` system
/// variables, `<named>` parameters and keywords (TRAORI, CALL) not words. The arguments of a
/// macro call (`G65` / `G66 P...`) are not axis words. validate(MachineProfile) refuses a
/// template with such a word (decision 0022): code blocks switch, the program moves.
[[nodiscard]] std::optional<std::string> motion_word(std::string_view block);

/// The text of a template block with its placeholders replaced (2 decimals each).
/// `power_max_w` scales `{power_pct}`. Blocks were checked by validate(MachineProfile).
[[nodiscard]] std::string expand_block(std::string_view block, double power_w, double powder_g_min,
                                       double power_max_w);

}  // namespace maxslice::machine
