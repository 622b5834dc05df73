// SCPI transactions with bounded waits: a timeout clears the link and asks the error queue
// why; a dropped link is reopened with exponential backoff; protocol errors are not retried
// (the answer was wrong, asking again hides a fault) but leave the link cleared.
#include "tocd/devices/scpi_client.hpp"

#include <algorithm>
#include <thread>

#include <fmt/format.h>

#include "tocd/core/log.hpp"
#include "trace.hpp"

namespace tocd::devices {
namespace {

std::string printable(std::string_view s) {
  std::string out;
  for (unsigned char c : s.substr(0, 60))
    out += (c >= 0x20 && c < 0x7F) ? std::string(1, static_cast<char>(c)) : fmt::format("\\x{:02X}", c);
  if (s.size() > 60) out += "...";
  return out;
}

bool is_text(std::string_view s) {
  return std::all_of(s.begin(), s.end(),
                     [](unsigned char c) { return (c >= 0x20 && c < 0x7F) || c == '\t'; });
}

}  // namespace

ScpiClient::ScpiClient(std::unique_ptr<ScpiLink> link, std::string instrument, ScpiClientOptions options)
    : link_(std::move(link)), instrument_(std::move(instrument)), options_(options) {
  if (!link_) throw ConfigError(instrument_ + ": no link to talk over");
  if (options_.timeout.count() <= 0) throw ConfigError(instrument_ + ": timeout must be positive");
  if (options_.retries < 0) throw ConfigError(instrument_ + ": retries must be >= 0");
}

void ScpiClient::command(std::string_view cmd) {
  transact(cmd, false, std::chrono::milliseconds{0});
}

std::string ScpiClient::query(std::string_view q, std::chrono::milliseconds extra) {
  return transact(q, true, extra);
}

double ScpiClient::query_number(std::string_view q, std::chrono::milliseconds extra) {
  return parse_scpi_number(query(q, extra), instrument_, std::string(q));
}

void ScpiClient::ensure_open(Clock::time_point deadline) {
  if (link_->is_open()) return;
  link_->open(deadline);
  if (opened_once_) ++reconnects_;
  opened_once_ = true;
}

void ScpiClient::recover_after_failure(LinkFailure kind) noexcept {
  if (kind == LinkFailure::disconnected) {
    link_->close();
    return;
  }
  try {
    if (link_->is_open()) link_->clear(Clock::now() + options_.timeout);
  } catch (const LinkError&) {
    link_->close();  // the next attempt reconnects
  }
}

std::optional<ScpiErrorEntry> ScpiClient::probe_error() noexcept {
  try {
    const auto deadline = Clock::now() + options_.timeout;
    ensure_open(deadline);
    link_->write("SYST:ERR?", deadline);
    return parse_scpi_error(link_->read(deadline), instrument_);
  } catch (const LinkError& e) {
    recover_after_failure(e.kind());
  } catch (const DeviceError&) {
    recover_after_failure(LinkFailure::protocol);
  }
  return std::nullopt;
}

std::string ScpiClient::transact(std::string_view message, bool expect_answer,
                                 std::chrono::milliseconds extra) {
  const std::string cmd(message);
  LinkFailure last_kind = LinkFailure::timeout;
  std::string last_detail;
  auto backoff = options_.backoff;
  for (int attempt = 0; attempt <= options_.retries; ++attempt) {
    if (attempt > 0) {
      ++retried_;
      std::this_thread::sleep_for(backoff);
      backoff = std::min(backoff * 2, options_.max_backoff);
    }
    const auto deadline = Clock::now() + options_.timeout + extra;
    try {
      ensure_open(deadline);
      if (trace_enabled()) trace_log().trace("{}: scpi -> {}", instrument_, printable(cmd));
      link_->write(message, deadline);
      if (!expect_answer) return {};
      std::string answer = link_->read(deadline);
      if (trace_enabled()) trace_log().trace("{}: scpi <- {}", instrument_, printable(answer));
      if (!is_text(answer)) {
        recover_after_failure(LinkFailure::protocol);
        throw ProtocolError(
            instrument_, cmd,
            fmt::format("the answer is not text: \"{}\" ({} bytes)", printable(answer), answer.size()));
      }
      return answer;
    } catch (const LinkError& e) {
      last_kind = e.kind();
      last_detail = e.what();
      logger("devices")->debug("{}: {}: attempt {} failed: {}", instrument_, cmd, attempt + 1, last_detail);
      recover_after_failure(e.kind());
      if (e.kind() == LinkFailure::protocol) throw ProtocolError(instrument_, cmd, last_detail);
      if (e.kind() == LinkFailure::timeout && expect_answer && cmd != "SYST:ERR?") {
        // A query the instrument refuses gets no answer; its error queue says why.
        if (const auto err = probe_error(); err && err->code != 0)
          throw InstrumentFault(
              instrument_, cmd,
              fmt::format("no answer; the instrument reports {},\"{}\"", err->code, err->message));
      }
    }
  }
  const int attempts = options_.retries + 1;
  if (last_kind == LinkFailure::timeout)
    throw TimeoutError(
        instrument_, cmd,
        fmt::format("no answer within {} ms ({} attempt{}): {}", (options_.timeout + extra).count(), attempts,
                    attempts == 1 ? "" : "s", last_detail));
  throw ConnectionError(instrument_, cmd,
                        fmt::format("link lost and not re-established ({} attempt{}): {}", attempts,
                                    attempts == 1 ? "" : "s", last_detail));
}

std::vector<ScpiErrorEntry> ScpiClient::drain_errors() {
  std::vector<ScpiErrorEntry> entries;
  for (int i = 0; i < options_.max_error_drain; ++i) {
    ScpiErrorEntry e = parse_scpi_error(query("SYST:ERR?"), instrument_);
    if (e.code == 0) return entries;
    entries.push_back(std::move(e));
  }
  throw ProtocolError(instrument_, "SYST:ERR?",
                      fmt::format("the error queue did not empty after {} reads", options_.max_error_drain));
}

void ScpiClient::check_errors(std::string_view after) {
  const auto entries = drain_errors();
  if (entries.empty()) return;
  std::string list;
  for (const auto& e : entries)
    list += fmt::format("{}{},\"{}\"", list.empty() ? "" : "; ", e.code, e.message);
  throw InstrumentFault(instrument_, std::string(after), "the instrument reports " + list);
}

}  // namespace tocd::devices
