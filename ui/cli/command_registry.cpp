#include "command_registry.hpp"

#include <utility>

namespace tocd::cli {

std::vector<CommandEntry>& command_registry() {
  static std::vector<CommandEntry> entries;  // function-local: safe during static init
  return entries;
}

CommandRegistration::CommandRegistration(std::string_view name, CommandInstaller install) {
  command_registry().push_back({name, std::move(install)});
}

}  // namespace tocd::cli
