// The accepted range of every number a project, world or robot file gives, in one table, each
// with the reason for its bounds. `sear check` accepts only what `sear run` can run: before these
// bounds, values such as gravity="0 0 -1e300", a chassis of 0.0001 kg, a wall 1e200 m high or a
// tree crown of 1e200 m made ODE abort the run with an assertion and no summary. The bounds are
// physical (what any robot, world or part could plausibly be, with a wide margin) rather than the
// edge of what ODE survives today, so that a typo (a missing decimal point, mm for m) is caught too.
// Units are those of the file: m, s, kg, N*m, V, Hz, degrees.
#pragma once

#include "scene/description.hpp"
#include "scene/element_reader.hpp"

namespace sear::ranges {

// ---- <run> ----
// Times become integer nanoseconds: 1e7 s (116 days) keeps them far inside int64.
inline const Range kDuration = Range::above(0, kMaxTime_s, "> 0 and <= 1e7 s");
inline const Range kScriptTime = Range::between(0, kMaxTime_s, "0..1e7 s");
// The noise generator takes a 32-bit seed from the file (the command line takes 64 bits).
inline const Range kSeed = Range::between(0, 4294967295.0, "0..4294967295");
// From one row every 100 s to one every microsecond (finer than any step).
inline const Range kTraceRate = Range::between(kMinTraceRate_hz, kMaxTraceRate_hz, "0.01..1e6 Hz");

// ---- <world> ----
// Each component. 100 m/s^2 (10 g) covers every body a robot drives on (Earth 9.81, Mars 3.71,
// the Moon 1.62) and a centrifuge rig; 1e300 made ODE abort.
inline const Range kGravity = Range::between(-100, 100, "-100..100 m/s^2");
// 10 us resolves the stiffest contact here; 10 ms is the coarsest step at which a wheel on a
// 1 ms-scale contact still settles, and the lockstep quantum must stay below a firmware's timers.
inline const Range kStep = Range::between(1e-5, 0.01, "between 0.00001 and 0.01 s");
// The iterative solver's sweeps: at least one; 1000 already costs ~250x the default step.
inline const Range kSolverIterations = Range::between(1, 1000, "1..1000");
inline const Range kLatitude = Range::between(-90, 90, "-90..90 degrees");
inline const Range kLongitude = Range::between(-180, 180, "-180..180 degrees");
// From the deepest ocean floor (-10 935 m) to the edge of space (100 km).
inline const Range kAltitude = Range::between(-11000, 100000, "-11000..100000 m");
inline const Range kDeclination = Range::between(-180, 180, "-180..180 degrees");
inline const Range kInclination = Range::between(-90, 90, "-90..90 degrees");
// The Earth's field lies between about 22 000 nT (South Atlantic) and 67 000 nT (the poles).
inline const Range kFieldIntensity = Range::between(1000, 100000, "1000..100000 nT");
// The World Magnetic Model's coefficients are for 2025-2030; a few years either side still holds.
inline const Range kMagneticYear = Range::between(2020, 2035, "2020..2035");
// Coulomb coefficients of real pairs stay below about 2 (rubber on dry concrete ~1, silicone on
// glass up to ~3); 10 leaves room for "never slips" while catching a slipped decimal point.
inline const Range kFriction = Range::between(0, 10, "0..10");
// Restitution: 0 (no bounce) to 1 (perfectly elastic); more would create energy.
inline const Range kBounce = Range::between(0, 1, "0..1");
// Positions in the world: 100 km from the origin, the distance a <pose> may be from <gps_origin>.
// Beyond it the local flat-earth frame is off by metres.
inline const Range kWorldXY = Range::between(-1e5, 1e5, "-100000..100000 m");
// Heights (terrain, a box's z): the terrain probe ray spans +-1e4 m (PhysicsWorld::terrain_height),
// and Everest is 8849 m above sea level.
inline const Range kHeight = Range::between(-1e4, 1e4, "-10000..10000 m");
// A heightmap's side: up to the 100 km a world may span, each side 2 * kWorldXY.
inline const Range kTerrainSide = Range::above(0, 2e5, "> 0 and <= 200000 m");
// One turn either way names every heading.
inline const Range kYaw = Range::between(-360, 360, "-360..360 degrees");
// A mesh's unit to metres: micrometre CAD files (1e-6) to kilometre-unit terrain (1e3), with margin.
inline const Range kMeshScale = Range::between(1e-6, 1e6, "1e-6..1e6");
// Obstacle sides, wall height and thickness, trunk radius: from 1 mm (a wire, a thin pole) to
// 1 km. A wall 1e200 m high made ODE abort.
inline const Range kObstacleSize = Range::between(0.001, 1000, "0.001..1000 m");
// 0 is a static obstacle; up to 1000 t (a loaded shipping container is 30 t).
inline const Range kObstacleMass = Range::between(0, 1e6, "0..1e6 kg");
// The tallest tree measured is 116 m.
inline const Range kTrunkHeight = Range::between(0.01, 200, "0.01..200 m");
// 0 for no crown; a 1e200 m crown made ODE abort.
inline const Range kCrownRadius = Range::between(0, 100, "0..100 m");

// ---- robots ----
// Positions of wheels, casters and sensors in the robot frame, and chassis sides: a robot from
// 1 mm to 100 m (a large mining truck is 15 m long).
inline const Range kRobotXYZ = Range::between(-100, 100, "-100..100 m");
inline const Range kChassisSide = Range::between(0.001, 100, "0.001..100 m");
// From a 10 g micro robot (a Kilobot is 16 g) to a 100 t machine. A 0.0001 kg chassis made ODE
// abort: its inertia is too small against the rover's own wheels and motors.
inline const Range kChassisMass = Range::between(0.01, 1e5, "0.01..100000 kg");
// Wheel and caster radius and width: a 1 mm micro wheel to a 10 m one (mining tyres are 2 m).
inline const Range kWheelSize = Range::between(0.001, 10, "0.001..10 m");
// 1 g to 10 t; a 1e6 kg wheel on the rover made ODE abort.
inline const Range kWheelMass = Range::between(0.001, 1e4, "0.001..10000 kg");
// Motors: kept wide, since the motor model is stable for any torque (sim/physics/dc_motor); the
// bounds only keep the numbers finite in every product the model forms. 1e6 N*m is past the
// largest wheel hub motors; 1e6 rpm past any rotating machine.
inline const Range kStallTorque = Range::above(0, 1e6, "> 0 and <= 1e6 N*m");
inline const Range kNoLoadRpm = Range::above(0, 1e6, "> 0 and <= 1e6 rpm");
inline const Range kNoLoadSpeed = Range::above(0, 1e5, "> 0 and <= 1e5 rad/s");
// From a 1 V coin-cell toy to 1000 V industrial DC drives.
inline const Range kVoltage = Range::between(0.1, 1000, "0.1..1000 V");
inline const Range kGearFriction = Range::between(0, 1e6, "0..1e6 N*m");
// Servo pulses: hobby servos take 500..2500 us; 400..2600 allows for trimmed ends.
inline const Range kPulse = Range::between(400, 2600, "400..2600 us");
// Hobby servos give 0.05..5 N*m, industrial ones up to ~100; 1e4 stays finite with margin.
inline const Range kServoTorque = Range::above(0, 1e4, "> 0 and <= 1e4 N*m");
// Full travel; steering beyond +-85 degrees has no turning centre left to aim at.
inline const Range kServoTravel = Range::between(1, 170, "1..170 degrees");
// Seconds per 60 degrees: the fastest digital servos take 0.03 s, sail winches several seconds.
inline const Range kServoSlew = Range::between(0.001, 1000, "0.001..1000 s");
// Continuous-rotation servos turn 40..150 rpm.
inline const Range kServoRpm = Range::above(0, 1e4, "> 0 and <= 10000 rpm");
inline const Range kDuty = Range::between(0, 1, "0..1");

// ---- <mcu> ----
// From a 1 kHz watch crystal divided down to a 1 GHz application core.
inline const Range kClock = Range::between(1e3, 1e9, "1e3..1e9 Hz");
inline const Range kHalCallCycles = Range::between(0, 1e6, "0..1e6");
// The ATmega2560's AVCC: 1.8 V (its minimum at 4 MHz) to 5.5 V (its maximum).
inline const Range kAvcc = Range::between(1.8, 5.5, "1.8..5.5 V");
// AREF: at least 1.0 V for the datasheet's ADC accuracy, at most AVCC's maximum.
inline const Range kAref = Range::between(1.0, 5.5, "1.0..5.5 V");
inline const Range kPitch = Range::between(-90, 90, "-90..90 degrees");
// Sharp's rangers see a spot a few centimetres wide at their far end: a narrow cone.
inline const Range kHalfAngle = Range::between(0, 45, "0..45 degrees");
inline const Range kResolution = Range::above(0, 45, "> 0 and <= 45 degrees");
inline const Range kMaxRange = Range::above(0, 100, "> 0 and <= 100 m");
inline const Range kNoiseV = Range::between(0, 1, "0..1 V");
// The GP2D15's datasheet gives 24 cm typical, 21..27 cm from unit to unit.
inline const Range kSwitchDistance = Range::between(0.21, 0.27, "0.21..0.27 m");
inline const Range kHysteresis = Range::between(0, 0.1, "0..0.1 m");
// Range noise of ultrasonic and laser rangers: up to a metre, which no part comes near.
inline const Range kRangeNoise = Range::between(0, 1, "0..1 m");
// From the surface's normal: 90 degrees would be a grazing ray.
inline const Range kIncidence = Range::above(0, 90, "> 0 and <= 90 degrees");
inline const Range kBumpWidth = Range::between(0, 2, "0..2 m");
inline const Range kBumpReach = Range::above(0, 0.2, "> 0 and <= 0.2 m");

// ---- names ----
// Names become parts of file names (ROBOT.MCU.uart3.tx.bin, trace_ROBOT.csv): two of them and
// the longest suffix stay far below the 255 bytes a file name may have.
constexpr std::size_t kMaxNameLength = 64;

}  // namespace sear::ranges
