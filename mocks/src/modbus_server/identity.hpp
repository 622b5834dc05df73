#pragma once

#include <cstdint>
#include <string_view>

namespace tocd::mocks {

/// Writes the shared map-version + identity block (input registers 99..147).
void write_identity_block(std::uint16_t* input_registers, std::uint16_t version, std::string_view vendor,
                          std::string_view model, std::string_view serial, std::string_view firmware);

}  // namespace tocd::mocks
