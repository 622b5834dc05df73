#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tocd/devices/capabilities.hpp"
#include "tocd/devices/instruments.hpp"
#include "tocd/devices/scpi_client.hpp"
#include "tocd/devices/usb_endpoint.hpp"

namespace tocd::devices {

/// A meter that speaks SCPI on a raw TCP socket (newline-terminated, port 5025 style).
struct ScpiTcpAddress {
  std::string host;
  int port = 5025;
};

/// A USBTMC meter: vendor/product id and, when several are attached, the serial number.
struct UsbtmcAddress {
  std::uint16_t vendor_id = 0x1313, product_id = 0;
  std::string serial;
};

struct PowerMeterOptions {
  double timeout_s = 2.0;         ///< per attempt of one command/query
  int retries = 2;                ///< extra attempts after a timeout or a dropped link
  double backoff_s = 0.05;        ///< first wait before a retry (doubles, at most 1 s)
  double zero_timeout_s = 20.0;   ///< zeroing must finish within this
  double zero_poll_s = 0.05;      ///< SENS:CORR:COLL:ZERO:STAT? poll interval
  double sample_time_s = 0.0003;  ///< time per averaged sample: lengthens waits for READ?/MEAS
  bool check_errors = true;       ///< SYST:ERR? after every setting
  /// A zeroed sensor in the dark reads its noise, which straddles zero: readings down to
  /// -negative_tolerance_W are kept as they are (clipping them would bias dark averages);
  /// anything more negative is an InvalidReading. 1 uW covers photodiode sensors (noise of
  /// nW) and the zero drift of thermal ones; a meter with no zero at all reads far beyond it.
  double negative_tolerance_W = 1e-6;
};

/// Answers at or above this magnitude mean "over range" (SCPI 9.9E37 convention).
inline constexpr double scpi_over_range = 9.0e37;
/// SCPI's code for "not a number" (a failed measurement).
inline constexpr double scpi_not_a_number = 9.91e37;

/// The channel a run records of a SCPI power meter: the optical power on its sensor, up to the
/// 0.5 W limit of the photodiode sensors of this command set (S121C class).
inline constexpr std::array<ChannelCapability, 1> scpi_power_meter_channels{{
    {"power", "W", 0.0, 0.5, 10.0},
}};
inline constexpr InstrumentCapabilities scpi_power_meter_capabilities{"power_meter", "power meter",
                                                                      scpi_power_meter_channels};

/// PowerMeter over SCPI (either transport) with the Thorlabs PM100-class command subset, plus
/// the SCPI operations the generic interface does not cover. Not thread-safe.
class ScpiPowerMeter : public PowerMeter {
 public:
  ScpiPowerMeter(std::unique_ptr<ScpiLink> link, std::string instrument, const PowerMeterOptions& options);

  const InstrumentCapabilities& describe() const override { return scpi_power_meter_capabilities; }
  Identity identity() override;                // *IDN?
  std::string sensor_identity() override;      // SYST:SENS:IDN?
  void set_wavelength_nm(double nm) override;  // SENS:CORR:WAV
  void set_auto_range(bool on) override;       // SENS:POW:DC:RANG:AUTO
  void set_averaging(int count) override;      // SENS:AVER:COUN
  void zero() override;                        // SENS:CORR:COLL:ZERO:INIT + poll STAT?
  PowerReading measure() override;             // MEAS:POW?

  void reset();                          // *RST, then the error queue is drained
  double wavelength_nm();                // SENS:CORR:WAV?
  bool auto_range();                     // SENS:POW:DC:RANG:AUTO?
  int averaging();                       // SENS:AVER:COUN?
  void configure_power();                // CONF:POW
  void initiate();                       // INIT
  PowerReading fetch();                  // FETC?
  PowerReading read();                   // READ?
  std::vector<ScpiErrorEntry> errors();  // SYST:ERR? until 0

  ScpiClient& client() noexcept { return client_; }

 private:
  PowerReading reading_from(std::string_view query);
  void set(const std::string& command);

  ScpiClient client_;
  PowerMeterOptions options_;
  int averaging_ = 1;  ///< last count set, to size the wait of a reading
};

/// Raw-TCP SCPI link (connects lazily; the first command opens it).
std::unique_ptr<ScpiLink> make_scpi_tcp_link(const ScpiTcpAddress& address);

std::unique_ptr<PowerMeter> connect_scpi_tcp_power_meter(const ScpiTcpAddress&,
                                                         const PowerMeterOptions& = {});
std::unique_ptr<PowerMeter> connect_usbtmc_power_meter(const UsbtmcAddress&, const PowerMeterOptions& = {});

/// The same drivers with their full SCPI surface. Both connect and read *IDN? before
/// returning, so a wrong address fails here with ConnectionError/TimeoutError.
std::unique_ptr<ScpiPowerMeter> open_scpi_tcp_power_meter(const ScpiTcpAddress&,
                                                          const PowerMeterOptions& = {});
std::unique_ptr<ScpiPowerMeter> open_usbtmc_power_meter(const UsbtmcAddress&, const PowerMeterOptions& = {});
/// A USBTMC meter behind any endpoint (the libusb one, or the simulated one of tocd::mocks).
std::unique_ptr<ScpiPowerMeter> open_usbtmc_power_meter(UsbEndpointOpener opener, std::string description,
                                                        const PowerMeterOptions& = {});

}  // namespace tocd::devices
