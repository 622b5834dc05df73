#include "output_paths.hpp"

#include <filesystem>
#include <system_error>

#include <fmt/format.h>
#include <unistd.h>

namespace tocd::cli {

namespace fs = std::filesystem;

namespace {

bool writable(const fs::path& p) {
  return ::access(p.c_str(), W_OK) == 0;
}

}  // namespace

std::string output_file_problem(const std::string& path) {
  if (path.empty()) return "the path is empty";
  std::error_code ec;
  const fs::path p(path);
  if (path.back() == '/' || fs::is_directory(p, ec))
    return fmt::format("'{}' is a directory; give a file name", path);
  // An existing file (or a device such as /dev/stdout) is written in place or replaced.
  if (fs::exists(p, ec) && !fs::is_regular_file(p, ec)) {
    return writable(p) ? "" : fmt::format("'{}' cannot be written", path);
  }
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) return fmt::format("the directory '{}' does not exist", dir.string());
  if (!writable(dir)) return fmt::format("the directory '{}' cannot be written", dir.string());
  return "";
}

std::string output_dir_problem(const std::string& path) {
  if (path.empty()) return "the path is empty";
  std::error_code ec;
  fs::path p(path);
  if (fs::exists(p, ec) && !fs::is_directory(p, ec))
    return fmt::format("'{}' exists and is not a directory", path);
  // The nearest existing ancestor is where the missing directories will be created.
  fs::path existing = p;
  while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, ec))
    return fmt::format("'{}' is not a directory, so '{}' cannot be created in it", existing.string(), path);
  if (!writable(existing)) return fmt::format("the directory '{}' cannot be written", existing.string());
  return "";
}

CLI::Validator output_file() {
  return CLI::Validator([](std::string& v) { return output_file_problem(v); }, "FILE");
}

CLI::Validator output_dir() {
  return CLI::Validator([](std::string& v) { return output_dir_problem(v); }, "DIR");
}

}  // namespace tocd::cli
