// `tocdlab version`: versions of tocdlab and the libraries it was built against, as JSON
// when asked (stored with bug reports and runs).
#include "tocd/core/version.hpp"

#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "output_naming.hpp"

namespace {

void install_version(CLI::App& root) {
  auto* cmd = root.add_subcommand("version", "Print tocdlab's version and build facts");
  auto json = std::make_shared<bool>(false);  // options outlive this function: shared state
  cmd->add_flag("--json", *json, "machine-readable output");
  cmd->callback([json] {
    nlohmann::json out = {
        {"tocdlab", std::string(tocd::version())}, {"compiler", __VERSION__}, {"cxx_standard", __cplusplus}};
    if (*json) {
      tocd::cli::print_json(out);
    } else {
      std::cout << "tocdlab " << tocd::version() << " (" << __VERSION__ << ")\n";
    }
  });
}

}  // namespace

TOCD_CLI_COMMAND(version, install_version);
