#include "help_format.h"

#include <algorithm>
#include <memory>
#include <sstream>
#include <vector>

namespace skelgrasp::cli {

bool isDetailGroup(const std::string& group) {
  return std::any_of(kDetailGroups.begin(), kDetailGroups.end(),
                     [&](const char* name) { return group == name; });
}

std::string HelpFormatter::make_help(const CLI::App* app, std::string name,
                                     CLI::AppFormatMode mode) const {
  // A subcommand expanded inside its parent's --help-all: CLI11's layout, every group shown.
  if (mode == CLI::AppFormatMode::Sub) return CLI::Formatter::make_help(app, name, mode);
  std::stringstream out;
  out << make_description(app) << make_usage(app, name) << make_positionals(app);
  std::vector<std::string> left_out;
  for (const std::string& group : app->get_groups()) {
    if (group.empty()) continue;  // CLI11's hidden options
    const auto options = app->get_options([&](const CLI::Option* option) {
      return option->get_group() == group && option->nonpositional();
    });
    if (options.empty()) continue;
    if (mode == CLI::AppFormatMode::Normal && isDetailGroup(group)) {
      left_out.push_back(group + " (" + std::to_string(options.size()) + ")");
      continue;
    }
    out << make_group(group, false, options);
  }
  if (!left_out.empty()) {
    out << "\nMore options, shown by --help-all: ";
    for (std::size_t i = 0; i < left_out.size(); ++i) out << (i > 0 ? ", " : "") << left_out[i];
    out << '\n';
  }
  out << make_subcommands(app, mode) << '\n' << make_footer(app);
  return out.str();
}

void setUpHelp(CLI::App& app) {
  app.formatter(std::make_shared<HelpFormatter>());
  app.set_help_all_flag("--help-all", "Print every option, the detailed ones too, and exit");
}

}  // namespace skelgrasp::cli
