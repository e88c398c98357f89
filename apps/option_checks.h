#pragma once
// Validity checks of the numeric command-line options. Every numeric option gets one of these,
// so a value that is not finite, negative where a count is meant, or outside the range in which
// it means something is refused at parse time with "--option: <problem>" (one line, exit 2; see
// main.cpp). The ranges show in --help next to the option's type. Limits that protect memory
// (octree resolution, Poisson depth, ...) are the stages' business, not these checks'.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <limits>
#include <string>

namespace skelgrasp::cli {

// Largest length an option may give, in metres: far beyond any table scene or object, small
// enough that squares and sums of lengths stay exact enough to compare.
constexpr double kMaxOptionLengthM = 1e3;
// Longest time limit, in seconds (about eleven days).
constexpr double kMaxTimeoutS = 1e6;
// Friction coefficients above this are no physical contact (rubber on rubber is about 1-2).
constexpr double kMaxFriction = 10;
// Largest dimensionless ratio or factor option (divisors, weights, spur factor).
constexpr double kMaxRatio = 1e6;
// Largest count (grasps, hypotheses, samples, objects): anything above is a typo, and it keeps
// products of counts far from overflowing 64 bits.
constexpr std::uint64_t kMaxCount = 1'000'000'000;
// Most repetitions of a benchmark run.
constexpr std::uint64_t kMaxRepeat = 1000;

// A finite floating-point number in [min, max].
CLI::Validator finiteIn(double min, double max);
// A finite floating-point number in (0, max].
CLI::Validator positiveFinite(double max);
// A length in metres, 0 allowed (usually "off"): [0, kMaxOptionLengthM].
CLI::Validator lengthOrZero();
// A positive length in metres: (0, kMaxOptionLengthM].
CLI::Validator positiveLength();
// A whole decimal number in [min, max] (no sign, no fraction, no exponent). Leading zeros are
// dropped, so "010" means ten (CLI11 alone would read it as octal eight). Rewrites the value:
// add it with Option::transform (Option::check would discard the rewrite).
CLI::Validator countIn(std::uint64_t min, std::uint64_t max);
// A mesh vertex budget: 0 ("never simplify") or at least the 4 vertices a closed mesh needs, up
// to kMaxCount. Add it with Option::transform, like countIn.
CLI::Validator vertexCountOrZero();
// A count of threads or parallel jobs, at least `min` (0 may mean "all cores" where documented).
// Values above std::thread::hardware_concurrency() are lowered to it with a warning: more
// threads than cores only add contention, and tens of thousands exhaust the process. Add it
// with Option::transform, like countIn.
CLI::Validator threadCount(int min);

// std::thread::hardware_concurrency(), at least 1 (it may report 0 when unknown).
int hardwareThreads();

// Safety net after parsing, for an option that was given no check: walks the parsed
// subcommands and throws CLI::ValidationError for a non-finite value of a FLOAT option or a
// negative value of a UINT option.
void checkParsedNumbers(const CLI::App& app);

// Every option's shown default must pass the option's own checks; throws std::logic_error
// naming the option otherwise (a programming error, found by any run of the program).
void checkDefaults(CLI::App& app);

// `message` on one line: CLI11 messages may span lines.
std::string oneLine(const std::string& message);

}  // namespace skelgrasp::cli
