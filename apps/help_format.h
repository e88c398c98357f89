#pragma once
// `--help` and `--help-all` of every command. Options in a detail group (kDetailGroups) are left
// out of `--help`, which names those groups in one line at its end; `--help-all` shows every
// option. An option is in the default group ("Options", shown by --help) unless its command puts
// it in one of these.
#include <CLI/CLI.hpp>

#include <array>
#include <string>

namespace skelgrasp::cli {

inline constexpr const char* kPlannerDetails = "Planner details";
inline constexpr const char* kRankingDetails = "Ranking details";
inline constexpr const char* kSkeletonDetails = "Skeleton details";
inline constexpr const char* kScanDetails = "Scan details";
inline constexpr const char* kSceneDetails = "Scene details";
inline constexpr std::array<const char*, 5> kDetailGroups = {
    kPlannerDetails, kRankingDetails, kSkeletonDetails, kScanDetails, kSceneDetails};

bool isDetailGroup(const std::string& group);

// CLI11's layout, except that in `--help` (AppFormatMode::Normal) the detail groups are replaced
// by one line naming them and their option counts.
class HelpFormatter : public CLI::Formatter {
 public:
  std::string make_help(const CLI::App* app, std::string name,
                        CLI::AppFormatMode mode) const override;
};

// Installs HelpFormatter and the --help-all flag on `app`. Call it before adding subcommands:
// they inherit both from their parent when they are created.
void setUpHelp(CLI::App& app);

}  // namespace skelgrasp::cli
