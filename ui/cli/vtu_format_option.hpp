#pragma once

#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "tocd/sim/vtk/vtu.hpp"

namespace tocd::cli {

/// `--vtu-format binary|ascii` (default binary): how the command's .vtu files store arrays.
inline CLI::Option* add_vtu_format_option(CLI::App* cmd, tocd::sim::vtk::Format& format) {
  using tocd::sim::vtk::Format;
  const std::map<std::string, Format> names{{"binary", Format::binary}, {"ascii", Format::ascii}};
  return cmd
      ->add_option("--vtu-format", format,
                   ".vtu storage: binary (zlib-compressed, the default) or ascii (plain text)")
      ->transform(CLI::CheckedTransformer(names, CLI::ignore_case))
      ->default_str("binary");
}

}  // namespace tocd::cli
