#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "output_paths.hpp"
#include "tocd/sim/vtk/vtu.hpp"

namespace tocd::cli {

/// `--vtu-format binary|ascii` (default binary): how the command's .vtu files store arrays.
inline CLI::Option* add_vtu_format_option(CLI::App* cmd, tocd::sim::vtk::Format& format) {
  return cmd
      ->add_option_function<std::string>(
          "--vtu-format", [&format](const std::string& name) { format = tocd::sim::vtk::parse_format(name); },
          ".vtu storage: binary (zlib-compressed) or ascii (plain text)")
      ->check(CLI::IsMember({"binary", "ascii"}))
      ->default_str("binary");
}

/// `--vtu FILE` (a file that can be written; `help` says what goes in it) and its
/// `--vtu-format`: a command that writes a .vtu file offers both.
inline void add_vtu_output_options(CLI::App* cmd, std::string& path, tocd::sim::vtk::Format& format,
                                   const std::string& help) {
  cmd->add_option("--vtu", path, help)->check(output_file());
  add_vtu_format_option(cmd, format);
}

}  // namespace tocd::cli
