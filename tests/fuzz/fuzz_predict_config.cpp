// The prediction config JSON of `tocdlab predict --config`: any of the three forms tocdlab
// writes (a bare config, `predict --json` output, a run's stored predictions.config_json),
// read as the command reads it, then range-checked. A request that passes must survive the
// way back through its canonical config (what a run stores).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace st = tocd::sim::study;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // `predict --config` reports a JSON syntax error itself before the document is read.
  const auto json = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) return 0;
  try {
    const st::ConfigDocument document = st::config_document_from_json(json);
    for (const st::PredictionRequest* r :
         {&document.step, document.baseline ? &*document.baseline : nullptr}) {
      if (!r) continue;
      st::validate(*r);
      const nlohmann::json canonical = st::to_config(*r);
      if (st::to_config(st::request_from_config(canonical)) != canonical) std::abort();
    }
  } catch (const tocd::Error&) {
  }
  return 0;
}
