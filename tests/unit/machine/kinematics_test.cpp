#include "maxslice/machine/kinematics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "machine_fixtures.hpp"

namespace maxslice::machine {
namespace {

using core::Vec3d;

constexpr double kTipToleranceMm = 1e-6;
constexpr double kDirectionToleranceRad = 1e-6;
constexpr double kExactDeg = 1e-9;
constexpr double kExactMm = 1e-9;

struct TableSetup {
    Kinematics kinematics = Kinematics::kTableAc;
    Vec3d pivot{};
    double offset_x = 0.0;
    double offset_y = 0.0;
    int tilt_sign = 1;
    int c_sign = 1;
    double tilt_min = -120.0;
    double tilt_max = 120.0;
    double c_min = -720.0;
    double c_max = 720.0;
    double retract = 10.0;
};

MachineProfile table_machine(const TableSetup& s) {
    MachineProfile m = testing::gm_machine();
    m.kinematics = s.kinematics;
    const std::string tilt = s.kinematics == Kinematics::kTableBc ? "B" : "A";
    m.axes = {{"X", -1000.0, 1000.0},
              {"Y", -1000.0, 1000.0},
              {"Z", -1000.0, 1000.0},
              {tilt, s.tilt_min, s.tilt_max},
              {"C", s.c_min, s.c_max}};
    TableProfile t;
    t.pivot_mm = s.pivot;
    t.c_offset_x_mm = s.offset_x;
    t.c_offset_y_mm = s.offset_y;
    t.tilt_direction = s.tilt_sign;
    t.c_direction = s.c_sign;
    t.retract_mm = s.retract;
    m.table = t;
    return m;
}

MachineKinematics make(const TableSetup& s) {
    auto k = MachineKinematics::create(table_machine(s));
    EXPECT_TRUE(k.has_value()) << k.error().describe();
    return *k;
}

double angle_between(const Vec3d& a, const Vec3d& b) {
    return std::atan2(core::norm(core::cross(a, b)), core::dot(a, b));
}

void expect_pose(const MachinePose& got, const MachinePose& want, const std::string& what) {
    EXPECT_NEAR(got.x, want.x, kExactMm) << what;
    EXPECT_NEAR(got.y, want.y, kExactMm) << what;
    EXPECT_NEAR(got.z, want.z, kExactMm) << what;
    EXPECT_NEAR(got.a_or_b_deg, want.a_or_b_deg, kExactDeg) << what;
    EXPECT_NEAR(got.c_deg, want.c_deg, kExactDeg) << what;
}

void expect_refused(const core::Result<MachinePose>& r, const std::vector<std::string>& fragments) {
    ASSERT_FALSE(r.has_value()) << "accepted, expected an error with " << fragments.front();
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    for (const auto& f : fragments) {
        EXPECT_NE(r.error().message.find(f), std::string::npos)
            << "`" << f << "` not in: " << r.error().describe();
    }
}

// Hand derivation, A/C table, both signs +1, pivot and offset 0. The nozzle sees the part
// direction R^-1 z with R = R_x(A) R_z(C). For A = 90, C = 90: R_z(90) (1, 0, 0) = (0, 1, 0)
// and R_x(90) (0, 1, 0) = (0, cos 90, sin 90) = (0, 0, 1), so +X is built at A = 90, C = 90;
// the other solution is A = -90, C = -90 (R_z(-90) (1, 0, 0) = (0, -1, 0), R_x(-90) of that
// = (0, 0, 1)). The tip at the pivot stays at the machine origin.
TEST(Kinematics, AcDirectionXHasTheHandDerivedAngles) {
    const MachineKinematics k = make({});
    const auto near_plus = k.inverse({0, 0, 0}, {1, 0, 0}, {0, 0, 0, 10.0, 10.0});
    ASSERT_TRUE(near_plus.has_value()) << near_plus.error().describe();
    expect_pose(*near_plus, {0, 0, 0, 90.0, 90.0}, "previous A 10, C 10");
    const auto near_minus = k.inverse({0, 0, 0}, {1, 0, 0}, {0, 0, 0, -80.0, -100.0});
    ASSERT_TRUE(near_minus.has_value()) << near_minus.error().describe();
    expect_pose(*near_minus, {0, 0, 0, -90.0, -90.0}, "previous A -80, C -100");
}

// B/C table: R = R_y(B) R_z(C). R_y(t) (x, 0, 0) = (x cos t, 0, -x sin t). Direction +X:
// B = -90, C = 0 gives R_y(-90) (1, 0, 0) = (0, 0, 1); the other solution is B = 90, C = 180
// (R_z(180) (1, 0, 0) = (-1, 0, 0), R_y(90) of that = (0, 0, 1)). From B = 0, C = 0 the first
// is 90 deg away, the second 270 deg.
TEST(Kinematics, BcDirectionXHasTheHandDerivedAngles) {
    const MachineKinematics k = make({.kinematics = Kinematics::kTableBc});
    const auto r = k.inverse({0, 0, 0}, {1, 0, 0}, {});
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    expect_pose(*r, {0, 0, 0, -90.0, 0.0}, "from zero");
    const auto other = k.inverse({0, 0, 0}, {1, 0, 0}, {0, 0, 0, 80.0, 170.0});
    ASSERT_TRUE(other.has_value()) << other.error().describe();
    expect_pose(*other, {0, 0, 0, 90.0, 180.0}, "from B 80, C 170");
}

// Pivot (10, 20, -50), A/C, signs +1. Direction +Y: R_x(90) (0, 1, 0) = (0, 0, 1), so A = 90,
// C = 0. The part point q = (0, 0, 10) sits at pivot + R_x(90) q = pivot + (0, -10, 0) =
// (10, 10, -50). With a_direction = -1 the controller's A is the opposite: A = -90.
TEST(Kinematics, PivotAndSignMoveTheLinearAxesAsDerivedByHand) {
    const TableSetup plus{.pivot = {10.0, 20.0, -50.0}};
    const auto r = make(plus).inverse({0, 0, 10}, {0, 1, 0}, {});
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    expect_pose(*r, {10.0, 10.0, -50.0, 90.0, 0.0}, "a_direction +1");

    TableSetup minus = plus;
    minus.tilt_sign = -1;
    const auto m = make(minus).inverse({0, 0, 10}, {0, 1, 0}, {});
    ASSERT_TRUE(m.has_value()) << m.error().describe();
    expect_pose(*m, {10.0, 10.0, -50.0, -90.0, 0.0}, "a_direction -1");

    const ToolPose f = make(minus).forward(*m);
    EXPECT_NEAR(core::norm(f.tip_mm - Vec3d{0, 0, 10}), 0.0, kExactMm);
    EXPECT_NEAR(angle_between(f.direction, {0, 1, 0}), 0.0, 1e-12);
}

// C offset (30, 0): C = 180 turns the part origin about (30, 0) onto (60, 0, 0). The direction
// stays +Z (singular), so the inverse keeps C at the previous 180.
TEST(Kinematics, COffsetIsTheCAxisPosition) {
    const MachineKinematics k = make({.offset_x = 30.0});
    const ToolPose f = k.forward({60.0, 0.0, 0.0, 0.0, 180.0});
    EXPECT_NEAR(core::norm(f.tip_mm), 0.0, kExactMm);
    EXPECT_NEAR(angle_between(f.direction, {0, 0, 1}), 0.0, 1e-12);
    const auto r = k.inverse({0, 0, 0}, {0, 0, 1}, {0, 0, 0, 0.0, 180.0});
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    expect_pose(*r, {60.0, 0.0, 0.0, 0.0, 180.0}, "C held at 180");
}

// Random poses inside the limits, for both tables, every sign and non-zero pivot and offset:
// forward, then inverse from an unrelated previous pose, then forward again returns the same
// tip and direction; from the pose itself as previous the inverse returns the pose.
// check_reach is a necessary condition: it never refuses a point that a pose inside the
// limits puts under the nozzle (any pose for the part's points; the table flat for its plate
// points), and it refuses points beyond what any pose reaches, naming them.
TEST(Kinematics, ReachTestRefusesOnlyWhatNoPoseReaches) {
    std::mt19937_64 rng(20261201);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto in = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    for (const Kinematics kin : {Kinematics::kTableAc, Kinematics::kTableBc}) {
        TableSetup s{
            .kinematics = kin, .pivot = {12.5, -40.0, -80.0}, .offset_x = 7.0, .offset_y = -3.0};
        const MachineKinematics k = make(s);
        for (int i = 0; i < 2000; ++i) {
            const MachinePose pose{in(-1000, 1000), in(-1000, 1000), in(-1000, 1000),
                                   in(s.tilt_min, s.tilt_max), in(s.c_min, s.c_max)};
            const Vec3d tip = k.forward(pose).tip_mm;
            ASSERT_TRUE(k.check_reach({tip}, {}, 0.0).has_value()) << i;
            MachinePose flat = pose;
            flat.a_or_b_deg = 0.0;
            const Vec3d on_plate = k.forward(flat).tip_mm;
            ASSERT_TRUE(k.check_reach({}, {on_plate}, 0.0).has_value()) << i;
        }
        // Far beyond the travel (more than 2000 mm from the pivot whatever the pose).
        const auto far = k.check_reach({{4000.0, 0.0, 0.0}}, {}, 0.0);
        ASSERT_FALSE(far.has_value());
        EXPECT_NE(far.error().message.find("does not fit the machine"), std::string::npos);
        EXPECT_NE(far.error().message.find("(4000.000, 0.000, 0.000)"), std::string::npos)
            << far.error().message;
        // 1500 mm from the C axis: within the bound for a tilted table (the travel's corners
        // lie up to 1810 mm from the pivot), but not on the plate with the table flat (the
        // X-Y travel's corners lie at most 1459 mm from the C axis).
        const Vec3d wide{1500.0 + 7.0, -3.0, 0.0};
        EXPECT_TRUE(k.check_reach({wide}, {}, 0.0).has_value());
        const auto flat_far = k.check_reach({}, {wide}, 0.0);
        ASSERT_FALSE(flat_far.has_value());
        EXPECT_NE(flat_far.error().message.find("on the plate"), std::string::npos);
        // The slack lets the outline overhang the travel by up to a track.
        EXPECT_TRUE(k.check_reach({}, {wide}, 100.0).has_value());
    }
    // "xyz": nothing tested here.
    auto xyz = MachineKinematics::create(testing::gm_machine());
    ASSERT_TRUE(xyz.has_value());
    EXPECT_TRUE(xyz->check_reach({{1e6, 0, 0}}, {{1e6, 0, 0}}, 0.0).has_value());
}

TEST(Kinematics, RoundTripOfRandomPosesInsideTheLimits) {
    std::mt19937_64 rng(20240611);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto in = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    int checked = 0;
    for (const Kinematics kin : {Kinematics::kTableAc, Kinematics::kTableBc}) {
        for (const int tilt_sign : {1, -1}) {
            for (const int c_sign : {1, -1}) {
                TableSetup s{.kinematics = kin,
                             .pivot = {12.5, -40.0, -80.0},
                             .offset_x = 7.0,
                             .offset_y = -3.0,
                             .tilt_sign = tilt_sign,
                             .c_sign = c_sign,
                             .tilt_min = -110.0,
                             .tilt_max = 120.0,
                             .c_min = -720.0,
                             .c_max = 720.0};
                const MachineKinematics k = make(s);
                for (int i = 0; i < 2000; ++i) {
                    const MachinePose pose{in(-300, 300), in(-300, 300), in(-300, 300),
                                           in(s.tilt_min, s.tilt_max), in(s.c_min, s.c_max)};
                    const MachinePose previous{in(-300, 300), in(-300, 300), in(-300, 300),
                                               in(s.tilt_min, s.tilt_max), in(s.c_min, s.c_max)};
                    const ToolPose want = k.forward(pose);
                    ASSERT_NEAR(core::norm(want.direction), 1.0, 1e-12);

                    const auto r = k.inverse(want.tip_mm, want.direction, previous);
                    ASSERT_TRUE(r.has_value()) << r.error().describe();
                    ASSERT_TRUE(k.check_limits(*r).has_value());
                    const ToolPose got = k.forward(*r);
                    ASSERT_LE(core::norm(got.tip_mm - want.tip_mm), kTipToleranceMm) << i;
                    ASSERT_LE(angle_between(got.direction, want.direction), kDirectionToleranceRad)
                        << i;

                    const auto same = k.inverse(want.tip_mm, want.direction, pose);
                    ASSERT_TRUE(same.has_value()) << same.error().describe();
                    ASSERT_NEAR(same->a_or_b_deg, pose.a_or_b_deg, 1e-7) << i;
                    ASSERT_NEAR(same->c_deg, pose.c_deg, 1e-7) << i;
                    ASSERT_LE(std::hypot(same->x - pose.x, same->y - pose.y, same->z - pose.z),
                              kTipToleranceMm)
                        << i;
                    ++checked;
                }
            }
        }
    }
    EXPECT_EQ(checked, 2 * 2 * 2 * 2000);
}

// Along the C axis C turns nothing: A (B) = 0 and C stays where it was, also after many turns.
TEST(Kinematics, SingularPoseHoldsC) {
    for (const Kinematics kin : {Kinematics::kTableAc, Kinematics::kTableBc}) {
        const MachineKinematics k = make({.kinematics = kin, .pivot = {0, 0, -40}, .offset_x = 5});
        for (const double c : {0.0, 37.0, -170.0, 400.0}) {
            const auto r = k.inverse({1, 2, 3}, {0, 0, 2}, {0, 0, 0, 15.0, c});
            ASSERT_TRUE(r.has_value()) << r.error().describe();
            EXPECT_NEAR(r->a_or_b_deg, 0.0, kExactDeg);
            EXPECT_DOUBLE_EQ(r->c_deg, c);
            const ToolPose f = k.forward(*r);
            EXPECT_LE(core::norm(f.tip_mm - Vec3d{1, 2, 3}), kTipToleranceMm);
            EXPECT_LE(angle_between(f.direction, {0, 0, 1}), kDirectionToleranceRad);
        }
    }
}

// A/C, A in [-30, 120] so only the positive tilt is possible. Direction (0, -1, 1) has
// phi = -90 deg, so C = 90 - phi = 180 (A = 45); tilted 5 deg further round (phi = -95 deg) it
// is C = 185, i.e. -175 + 360 k. The unwinding takes the equivalent nearest the previous C
// that C's limits allow.
TEST(Kinematics, CUnwindsToTheNearestTurnInsideItsLimits) {
    const double phi = -95.0 * std::numbers::pi / 180.0;
    const Vec3d d{std::cos(phi), std::sin(phi), 1.0};
    const auto c_for = [&](double c_min, double c_max, double previous_c) {
        const MachineKinematics k =
            make({.tilt_min = -30.0, .tilt_max = 120.0, .c_min = c_min, .c_max = c_max});
        const auto r = k.inverse({0, 0, 0}, d, {0, 0, 0, 45.0, previous_c});
        EXPECT_TRUE(r.has_value()) << r.error().describe();
        if (!r) return std::nan("");
        EXPECT_NEAR(r->a_or_b_deg, 45.0, kExactDeg);
        return r->c_deg;
    };
    EXPECT_NEAR(c_for(-200, 200, 170.0), 185.0, kExactDeg);
    EXPECT_NEAR(c_for(-200, 200, -170.0), -175.0, kExactDeg);
    EXPECT_NEAR(c_for(-180, 180, 170.0), -175.0, kExactDeg);  // 185 is beyond the limit
    EXPECT_NEAR(c_for(-360, 360, 350.0), 185.0, kExactDeg);
    EXPECT_NEAR(c_for(-360, 360, -350.0), -175.0, kExactDeg);
    EXPECT_NEAR(c_for(-3600, 3600, 1000.0), 905.0, kExactDeg);  // 185 + 2 turns
    EXPECT_NEAR(c_for(-3600, 3600, -3590.0), -3415.0, kExactDeg);

    // Exactly C = 180 on a [-180, 180] axis: both ends are the same turn; the nearer one wins.
    const Vec3d d180{0.0, -1.0, 1.0};
    const MachineKinematics k =
        make({.tilt_min = -30.0, .tilt_max = 120.0, .c_min = -180.0, .c_max = 180.0});
    const auto up = k.inverse({0, 0, 0}, d180, {0, 0, 0, 0.0, 150.0});
    ASSERT_TRUE(up.has_value()) << up.error().describe();
    EXPECT_NEAR(up->c_deg, 180.0, kExactDeg);
    const auto down = k.inverse({0, 0, 0}, d180, {0, 0, 0, 0.0, -150.0});
    ASSERT_TRUE(down.has_value()) << down.error().describe();
    EXPECT_NEAR(down->c_deg, -180.0, kExactDeg);
}

// Direction +X (A/C: A 90, C 90 or A -90, C -90). From A -80, C 90 the weighted distances are
// 170 + 0 and 10 + 180: equal weights take the first; a tilt weight of 10 takes the second.
TEST(Kinematics, NearestSolutionFollowsTheWeights) {
    const MachineKinematics k = make({});
    const MachinePose previous{0, 0, 0, -80.0, 90.0};
    const auto equal = k.inverse({0, 0, 0}, {1, 0, 0}, previous);
    ASSERT_TRUE(equal.has_value()) << equal.error().describe();
    expect_pose(*equal, {0, 0, 0, 90.0, 90.0}, "equal weights");
    const auto heavy_tilt = k.inverse({0, 0, 0}, {1, 0, 0}, previous, {.tilt = 10.0, .c = 1.0});
    ASSERT_TRUE(heavy_tilt.has_value()) << heavy_tilt.error().describe();
    expect_pose(*heavy_tilt, {0, 0, 0, -90.0, -90.0}, "tilt weight 10");
}

// When one solution is outside the limits the other is taken even when it is farther. Its C,
// 90, is half a turn from the previous -90 either way (90 or -270): the less wound one wins.
TEST(Kinematics, TheOtherSolutionIsTakenWhenOneIsOutOfLimits) {
    const MachineKinematics k = make({.tilt_min = -30.0, .tilt_max = 120.0});
    const auto r = k.inverse({0, 0, 0}, {1, 0, 0}, {0, 0, 0, -25.0, -90.0});
    ASSERT_TRUE(r.has_value()) << r.error().describe();
    expect_pose(*r, {0, 0, 0, 90.0, 90.0}, "A -90 is beyond -30");
}

TEST(Kinematics, UnreachableDirectionNamesTheAxis) {
    // Straight down needs A = 180: beyond [-120, 120] for both solutions.
    expect_refused(make({}).inverse({0, 0, 0}, {0, 0, -1}, {}),
                   {"no pose", "A = 180.000 deg", "machine.axes.A [-120, 120]", "A = -180.000"});
    // Tilted 150 deg from the C axis on a B/C table.
    const double t = 150.0 * std::numbers::pi / 180.0;
    expect_refused(make({.kinematics = Kinematics::kTableBc})
                       .inverse({0, 0, 0}, {std::sin(t), 0, std::cos(t)}, {}),
                   {"machine.axes.B"});
    // C limited to [-10, 10]: direction +X needs C = 90 or -90.
    expect_refused(make({.c_min = -10.0, .c_max = 10.0}).inverse({0, 0, 0}, {1, 0, 0}, {}),
                   {"machine.axes.C [-10, 10]"});
    // A tip far outside the travel.
    expect_refused(make({}).inverse({5000, 0, 0}, {0, 0, 1}, {}), {"X = ", "machine.axes.X"});
    expect_refused(make({}).inverse({0, 0, 0}, {0, 0, 0}, {}), {"zero direction"});
}

// Between two orientations: straight up along the tool axis by retract_mm above the higher
// of the two, turn there, across above the target.
TEST(Kinematics, ReorientationRetractsAlongTheToolAxisBeforeTurning) {
    const MachineKinematics k = make({.pivot = {5, 5, -60}, .offset_x = 4, .retract = 10.0});
    const MachinePose from{20.0, -5.0, 3.0, 0.0, 0.0};
    const MachinePose to{-10.0, 8.0, 7.0, 30.0, 90.0};
    const auto path = k.reorientation(from, to);
    ASSERT_TRUE(path.has_value()) << path.error().describe();
    ASSERT_EQ(path->size(), 3u);
    const auto& p = *path;
    for (const MachinePose& q : p) EXPECT_DOUBLE_EQ(q.z, 17.0);
    // First the retract: rotary unchanged, so the tip moves along the part's build direction.
    EXPECT_DOUBLE_EQ(p[0].a_or_b_deg, from.a_or_b_deg);
    EXPECT_DOUBLE_EQ(p[0].c_deg, from.c_deg);
    const ToolPose a = k.forward(from);
    const ToolPose b = k.forward(p[0]);
    EXPECT_LE(core::norm(b.tip_mm - (a.tip_mm + a.direction * 14.0)), kTipToleranceMm);
    // The turn with the linear axes still.
    EXPECT_DOUBLE_EQ(p[1].x, from.x);
    EXPECT_DOUBLE_EQ(p[1].y, from.y);
    EXPECT_DOUBLE_EQ(p[1].a_or_b_deg, to.a_or_b_deg);
    EXPECT_DOUBLE_EQ(p[1].c_deg, to.c_deg);
    // Above the target: the approach to `to` is along the tool axis.
    const ToolPose above = k.forward(p[2]);
    const ToolPose target = k.forward(to);
    EXPECT_LE(core::norm(above.tip_mm - (target.tip_mm + target.direction * 10.0)),
              kTipToleranceMm);

    EXPECT_TRUE(k.reorientation(from, {1.0, 2.0, 3.0, 0.0, 0.0})->empty());

    const MachineKinematics tall = make({.retract = 500.0});
    const auto over = tall.reorientation({0, 0, 600, 0, 0}, {0, 0, 600, 10, 0});
    ASSERT_FALSE(over.has_value());
    EXPECT_NE(over.error().message.find("machine.axes.Z.max"), std::string::npos);
    EXPECT_NE(over.error().message.find("machine.table.retract_mm"), std::string::npos);
}

// Turning A from 0 to 90 deg over a point 13.75 mm off the A axis on the +Y side would end
// with the tip 13.75 mm under the plate's level: the tip first moves across (machine Y) to the
// nearest point from which the head stays above the plate by the nozzle's clearance through
// the whole turn. Over a point already clear the sequence is the plain retract, turn, cross;
// a turn from -90 to +90 is made in two halves. B tables move across in X.
TEST(Kinematics, TheTableTurnsWithTheHeadAboveThePlate) {
    const NozzleProfile nozzle{};  // the machine has no [machine.nozzle]: the defaults
    const MachineKinematics k = make({.retract = 10.0});
    const MachinePose from{5.0, 13.75, 5.0, 0.0, 0.0};
    const MachinePose to{0.0, -30.0, 20.0, 90.0, 0.0};
    const auto path = k.reorientation(from, to);
    ASSERT_TRUE(path.has_value()) << path.error().describe();
    ASSERT_EQ(path->size(), 4u);
    const auto& p = *path;
    EXPECT_DOUBLE_EQ(p[1].x, from.x);
    EXPECT_DOUBLE_EQ(p[1].z, p[0].z);
    EXPECT_DOUBLE_EQ(p[1].a_or_b_deg, from.a_or_b_deg);
    EXPECT_LT(p[1].y, -20.0);  // the cone's rim reaches 23 mm across
    EXPECT_DOUBLE_EQ(p[2].y, p[1].y);
    EXPECT_DOUBLE_EQ(p[2].a_or_b_deg, to.a_or_b_deg);
    for (int i = 0; i <= 90; ++i) {
        const MachinePose at{p[1].x, p[1].y, p[1].z, static_cast<double>(i), 0.0};
        EXPECT_GE(testing::head_floor(k, nozzle, at), nozzle.clearance_mm * 0.99) << i << " deg";
    }
    // The nearest such point, with the turn's 0.5 mm slack over the clearance
    // (kinematics.cpp): a little less far across and the end of the turn is lower than that.
    const double slack = 0.5;
    const MachinePose nearer{p[1].x, p[1].y + 0.5, p[1].z, 90.0, 0.0};
    EXPECT_LT(testing::head_floor(k, nozzle, nearer), nozzle.clearance_mm + slack);
    // Without the move across the turn would reach under the plate.
    EXPECT_LT(testing::head_floor(k, nozzle, {from.x, from.y, p[0].z, 90.0, 0.0}), 0.0);

    const auto clear = k.reorientation({5.0, -40.0, 5.0, 0.0, 0.0}, to);
    ASSERT_TRUE(clear.has_value());
    EXPECT_EQ(clear->size(), 3u);
    // From -90 to +90 no one point keeps the head up: the turn stops at the flat table and
    // goes on over another point; every tilt of both halves keeps the head above the plate.
    const auto both_ways = k.reorientation({5.0, 13.75, 5.0, -90.0, 0.0}, to);
    ASSERT_TRUE(both_ways.has_value());
    bool flat = false;
    for (std::size_t i = 1; i < both_ways->size(); ++i) {
        const MachinePose& a = (*both_ways)[i - 1];
        const MachinePose& b = (*both_ways)[i];
        flat = flat || b.a_or_b_deg == 0.0;
        if (a.a_or_b_deg == b.a_or_b_deg) continue;
        EXPECT_DOUBLE_EQ(a.y, b.y);
        for (int j = 0; j <= 90; ++j) {
            const double t = a.a_or_b_deg + (b.a_or_b_deg - a.a_or_b_deg) * j / 90.0;
            const MachinePose at{a.x, a.y, a.z, t, 0.0};
            EXPECT_GE(testing::head_floor(k, nozzle, at), nozzle.clearance_mm * 0.99) << t;
        }
    }
    EXPECT_TRUE(flat);
    EXPECT_DOUBLE_EQ(both_ways->back().a_or_b_deg, to.a_or_b_deg);

    const MachineKinematics b = make({.kinematics = Kinematics::kTableBc, .retract = 10.0});
    const auto b_path = b.reorientation({-13.75, 5.0, 5.0, 0.0, 0.0}, {0.0, 0.0, 20.0, 90.0, 0.0});
    ASSERT_TRUE(b_path.has_value());
    ASSERT_EQ(b_path->size(), 4u);
    EXPECT_DOUBLE_EQ((*b_path)[1].y, 5.0);
    EXPECT_NE((*b_path)[1].x, -13.75);
    for (int i = 0; i <= 90; ++i) {
        const MachinePose at{(*b_path)[1].x, 5.0, (*b_path)[1].z, static_cast<double>(i), 0.0};
        EXPECT_GE(testing::head_floor(b, nozzle, at), nozzle.clearance_mm * 0.99) << i << " deg";
    }
}

// The clearance height raises z_safe when it is above both poses; the Z limit still applies.
TEST(Kinematics, ReorientationClimbsToTheClearanceHeight) {
    const MachineKinematics k = make({.retract = 10.0});
    const MachinePose from{20.0, -5.0, 3.0, 0.0, 0.0};
    const MachinePose to{-10.0, 8.0, 7.0, 30.0, 90.0};
    const auto high = k.reorientation(from, to, 250.0);
    ASSERT_TRUE(high.has_value()) << high.error().describe();
    ASSERT_EQ(high->size(), 3u);
    for (const MachinePose& q : *high) EXPECT_DOUBLE_EQ(q.z, 260.0);
    const auto low = k.reorientation(from, to, -40.0);
    ASSERT_TRUE(low.has_value());
    for (const MachinePose& q : *low) EXPECT_DOUBLE_EQ(q.z, 17.0);
    const auto over = k.reorientation(from, to, 995.0);
    ASSERT_FALSE(over.has_value());
    EXPECT_NE(over.error().message.find("machine.axes.Z.max"), std::string::npos);
    EXPECT_NE(over.error().message.find("clearance height 995.000 mm"), std::string::npos);
    EXPECT_DOUBLE_EQ(*k.safe_height(3.0, 7.0, 5.0), 17.0);
    EXPECT_FALSE(k.safe_height(3.0, 7.0, NAN).has_value());
}

// pose_at places the part tip under the nozzle for given rotary values: forward() gives the
// tip back, and inverse() agrees with it at its own angles.
TEST(Kinematics, PoseAtPutsTheTipUnderTheNozzle) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coord(-80.0, 80.0);
    std::uniform_real_distribution<double> angle(-110.0, 110.0);
    for (const TableSetup& s :
         {TableSetup{.pivot = {10, 20, -50}, .offset_x = 4, .offset_y = -6, .tilt_sign = -1},
          TableSetup{.kinematics = Kinematics::kTableBc,
          .pivot = {-15, 5, -40},
          .offset_x = -3,
          .c_sign = -1}}) {
        const MachineKinematics k = make(s);
        for (int i = 0; i < 50; ++i) {
            const Vec3d q{coord(rng), coord(rng), coord(rng)};
            const double a = angle(rng), c = 3.0 * angle(rng);
            const MachinePose p = k.pose_at(q, a, c);
            EXPECT_EQ(p.a_or_b_deg, a);
            EXPECT_EQ(p.c_deg, c);
            EXPECT_LE(core::norm(k.forward(p).tip_mm - q), kTipToleranceMm);
            const auto inv = k.inverse(q, k.forward(p).direction, p);
            ASSERT_TRUE(inv.has_value()) << inv.error().describe();
            expect_pose(*inv, k.pose_at(q, inv->a_or_b_deg, inv->c_deg), "inverse vs pose_at");
        }
    }
    auto xyz = MachineKinematics::create(testing::gm_machine());
    ASSERT_TRUE(xyz.has_value());
    expect_pose(xyz->pose_at({1, 2, 3}, 45.0, 90.0), {1, 2, 3, 0, 0}, "xyz ignores rotary");
}

TEST(Kinematics, XyzIsTheIdentityAndCannotTilt) {
    auto k = MachineKinematics::create(testing::gm_machine());
    ASSERT_TRUE(k.has_value()) << k.error().describe();
    const ToolPose f = k->forward({1.0, 2.0, 3.0, 0.0, 0.0});
    EXPECT_EQ(f.tip_mm, (Vec3d{1.0, 2.0, 3.0}));
    EXPECT_EQ(f.direction, (Vec3d{0.0, 0.0, 1.0}));
    const auto r = k->inverse({1, 2, 3}, {0, 0, 1}, {});
    ASSERT_TRUE(r.has_value());
    expect_pose(*r, {1, 2, 3, 0, 0}, "xyz");
    expect_refused(k->inverse({1, 2, 3}, {0, 1, 1}, {}), {"cannot tilt"});
    EXPECT_FALSE(k->reorientation({}, {1, 1, 1, 0, 0})->size());
}

TEST(Kinematics, CreateRefusesATableMachineWithoutItsTable) {
    MachineProfile m = table_machine({});
    m.table.reset();
    const auto k = MachineKinematics::create(m);
    ASSERT_FALSE(k.has_value());
    EXPECT_NE(k.error().message.find("machine.table"), std::string::npos);
}

}  // namespace
}  // namespace maxslice::machine
