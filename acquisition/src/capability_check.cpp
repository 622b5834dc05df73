#include "capability_check.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "tocd/acquisition/engine.hpp"

namespace tocd::acquisition {

namespace {

std::string names(auto&& list) {
  std::string out;
  for (const auto& n : list) out += (out.empty() ? "" : ", ") + std::string(n);
  return out.empty() ? "none" : out;
}

}  // namespace

void require_channels(const devices::InstrumentCapabilities& capabilities,
                      std::initializer_list<std::string_view> expected) {
  const auto& have = capabilities.channels;
  const bool same =
      have.size() == expected.size() &&
      std::equal(expected.begin(), expected.end(), have.begin(),
                 [](std::string_view name, const devices::ChannelCapability& c) { return c.name == name; });
  if (same) return;
  std::vector<std::string_view> described;
  for (const auto& c : have) described.push_back(c.name);
  throw EngineError(
      fmt::format("the {} driver describes the channels [{}]; the run engine records a {} as [{}]",
                  capabilities.title, names(described), capabilities.title, names(expected)));
}

}  // namespace tocd::acquisition
