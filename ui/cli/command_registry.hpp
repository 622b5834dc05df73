#pragma once

#include <functional>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

namespace tocd::cli {

/// Adds one subcommand (with its options and callback) to the root `tocdlab` app.
using CommandInstaller = std::function<void(CLI::App& root)>;

struct CommandEntry {
  std::string_view name;
  CommandInstaller install;
};

/// Every subcommand compiled into the executable, in registration order.
std::vector<CommandEntry>& command_registry();

/// Registers a subcommand at static-initialisation time; use TOCD_CLI_COMMAND.
struct CommandRegistration {
  CommandRegistration(std::string_view name, CommandInstaller install);
};

}  // namespace tocd::cli

/// In a commands/<name>.cpp: TOCD_CLI_COMMAND(name, [](CLI::App& root) { ... });
#define TOCD_CLI_COMMAND(name, installer)                                 \
  static const ::tocd::cli::CommandRegistration tocd_cli_command_##name { \
#name, installer                                                      \
  }
