#include <QApplication>
#include <QCommandLineParser>
#include <QCoreApplication>
#include <QDir>
#include <QTemporaryDir>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "demo.hpp"
#include "main_window.hpp"
#include "simulation_view.hpp"
#include "tocd/core/runtime_dir.hpp"
#include "tocd/core/version.hpp"
#include "tocd/mocks/sample_truth.hpp"

namespace {

// Qt's xcb and wayland platforms abort the process when they find no display; an explicit
// QT_QPA_PLATFORM (offscreen, vnc, ...) is the user's choice and is trusted.
bool display_available() {
  const auto set = [](const char* name) {
    const char* v = std::getenv(name);
    return v != nullptr && *v != '\0';
  };
  return set("QT_QPA_PLATFORM") || set("DISPLAY") || set("WAYLAND_DISPLAY");
}

// The window's command line: the options and, after parsing, their values.
struct CommandLine {
  QCommandLineParser cli;
  const QCommandLineOption help = cli.addHelpOption();
  // -V/--version as in `tocdlab` (Qt's own version option is -v).
  const QCommandLineOption version{QStringList{QStringLiteral("V"), QStringLiteral("version")},
                                   QStringLiteral("Displays version information.")};
  const QCommandLineOption demo{QStringLiteral("demo"),
                                QStringLiteral("Run the demo protocol on the simulated lab, then exit.")};
  const QCommandLineOption screenshot{QStringLiteral("screenshot"),
                                      QStringLiteral("With --demo: save a picture of the window to FILE."),
                                      QStringLiteral("FILE")};
  const QCommandLineOption db{
      QStringLiteral("db"),
      QStringLiteral("Record into this database (default: a temporary one for --demo)."),
      QStringLiteral("FILE")};
  const QCommandLineOption photons{QStringLiteral("photons"), QStringLiteral("Photons per prediction."),
                                   QStringLiteral("N")};
  const QCommandLineOption clock{QStringLiteral("clock-factor"),
                                 QStringLiteral("Simulated seconds per real second for the simulated lab."),
                                 QStringLiteral("F")};
  // The simulated sample's truth, as `tocdlab demo` takes it (tocd/mocks/sample_truth.hpp).
  const QCommandLineOption truth_seed{
      bare(tocd::mocks::kSampleTruthSeedOption),
      QStringLiteral(
          "Draw the simulated sample's truth (every --truth-* not given) from its documented ranges "
          "with this seed."),
      QStringLiteral("N")};
  std::vector<QCommandLineOption> truth_options;

  double clock_factor = 1.0;
  qulonglong photon_count = 0;
  tocd::mocks::SampleTruth truth;

  CommandLine() {
    cli.setApplicationDescription(QStringLiteral("tocdlab workbench window"));
    cli.addOptions({version, demo, screenshot, db, photons, clock, truth_seed});
    for (const auto& f : tocd::mocks::kSampleTruthFields) {
      const tocd::mocks::TruthRange r = tocd::mocks::sample_truth_limits().*f.range;
      truth_options.emplace_back(
          bare(f.option),
          QStringLiteral("The simulated sample's %1 (default %2, accepted %3 to %4; as in tocdlab demo).")
              .arg(QString::fromUtf8(f.name))
              .arg(tocd::mocks::SampleTruth{}.*f.value)
              .arg(r.lo)
              .arg(r.hi),
          QStringLiteral("X"));
      cli.addOption(truth_options.back());
    }
  }
  static QString bare(const char* option) { return QString::fromUtf8(option + 2); }  // no "--"

  // Parses; an exit code when the process ends here (--help, --version, a usage error). The
  // command line is read before the QApplication exists: a QApplication aborts without a
  // display, and --help, --version and usage errors need none (docs/cli.md: exit 0 / 2).
  std::optional<int> parse(int argc, char** argv) {
    const QCoreApplication console(argc, argv);
    QCoreApplication::setApplicationName(QStringLiteral("tocdlab-gui"));
    QCoreApplication::setApplicationVersion(QString::fromUtf8(tocd::version().data()));
    if (!cli.parse(QCoreApplication::arguments())) {
      std::fprintf(stderr, "tocdlab-gui: usage error: %s\nRun with --help for more information.\n",
                   qPrintable(cli.errorText()));
      return 2;
    }
    if (cli.isSet(help)) {
      std::fputs(qPrintable(cli.helpText()), stdout);
      return 0;
    }
    if (cli.isSet(version)) {
      std::printf("tocdlab-gui %s\n", std::string(tocd::version()).c_str());
      return 0;
    }
    return std::nullopt;
  }

  // Values are checked here too, before a display is needed: a usage error is exit 2 with or
  // without one.
  std::optional<int> read_values() {
    bool number_ok = true;
    clock_factor = cli.isSet(clock) ? cli.value(clock).toDouble(&number_ok) : 1.0;
    if (!number_ok || !(clock_factor > 0) || !std::isfinite(clock_factor)) {
      std::fprintf(stderr, "tocdlab-gui: usage error: --clock-factor must be a positive number, got '%s'\n",
                   qPrintable(cli.value(clock)));
      return 2;
    }
    photon_count = cli.isSet(photons) ? cli.value(photons).toULongLong(&number_ok) : 0;
    if (!number_ok || (cli.isSet(photons) && photon_count == 0)) {
      std::fprintf(stderr, "tocdlab-gui: usage error: --photons must be a positive whole number, got '%s'\n",
                   qPrintable(cli.value(photons)));
      return 2;
    }
    if (auto code = read_truth()) return code;
    if (cli.isSet(screenshot) && !cli.isSet(demo)) {
      std::fprintf(stderr, "tocdlab-gui: usage error: --screenshot needs --demo\n");
      return 2;
    }
    return std::nullopt;
  }

  std::optional<int> read_truth() {
    bool number_ok = true;
    if (cli.isSet(truth_seed)) {
      const qulonglong seed = cli.value(truth_seed).toULongLong(&number_ok);
      if (!number_ok) {
        std::fprintf(stderr, "tocdlab-gui: usage error: %s must be a whole number >= 0, got '%s'\n",
                     tocd::mocks::kSampleTruthSeedOption, qPrintable(cli.value(truth_seed)));
        return 2;
      }
      truth = tocd::mocks::draw_sample_truth(seed);
    }
    for (std::size_t i = 0; i < truth_options.size(); ++i) {
      if (!cli.isSet(truth_options[i])) continue;
      const auto& f = tocd::mocks::kSampleTruthFields[i];
      const tocd::mocks::TruthRange r = tocd::mocks::sample_truth_limits().*f.range;
      const double v = cli.value(truth_options[i]).toDouble(&number_ok);
      if (!number_ok || !std::isfinite(v) || v < r.lo || v > r.hi) {
        std::fprintf(stderr,
                     "tocdlab-gui: usage error: %s: '%s' is out of range: accepted from %g up to %g\n",
                     f.option, qPrintable(cli.value(truth_options[i])), r.lo, r.hi);
        return 2;
      }
      truth.*f.value = v;
    }
    return std::nullopt;
  }
};

// The window, with the simulated lab as the command line sets it; with --demo, the demo driven
// to its end.
int run_window(int argc, char** argv, const CommandLine& c) {
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("tocdlab"));
  QApplication::setOrganizationName(QStringLiteral("tocdlab"));
  QApplication::setApplicationVersion(QString::fromUtf8(tocd::version().data()));

  tocd::gui::MainWindow window;
  if (c.cli.isSet(c.photons)) {
    window.simulation_view()->set_photons(c.photon_count);
  } else if (c.cli.isSet(c.demo)) {
    window.simulation_view()->set_photons(20000);  // enough for a picture, quick on two cores
  }
  window.set_sample_truth(c.truth);
  auto lab = window.simulated_lab_options();
  // Real time: the demo protocol polls the tester at 1 kHz, and a faster clock asks that much
  // more of the loopback link while the window draws and the predictions run in the same
  // process (at x5 a busy machine kept up with 3,000 of the 5,000 readings a second).
  lab.clock_factor = c.clock_factor;
  window.set_simulated_lab_options(lab);
  window.show();
  if (!c.cli.isSet(c.demo)) {
    if (c.cli.isSet(c.db)) window.set_record_database(c.cli.value(c.db));
    return QApplication::exec();
  }

  QTemporaryDir scratch;
  window.set_record_database(c.cli.isSet(c.db) ? c.cli.value(c.db)
                                               : scratch.filePath(QStringLiteral("demo.tocdlab")));
  tocd::gui::DemoDriver driver(window, c.cli.value(c.screenshot));
  QObject::connect(&driver, &tocd::gui::DemoDriver::done, &app, [](int code) { QApplication::exit(code); });
  driver.start();
  const int code = QApplication::exec();
  std::fprintf(stderr, "tocdlab-gui --demo: %s (database %s)\n", code == 0 ? "ok" : "failed",
               qPrintable(window.record_database()));
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CommandLine c;
  if (auto code = c.parse(argc, argv)) return *code;
  if (auto code = c.read_values()) return *code;
  tocd::ensure_runtime_dir();
  if (!display_available()) {
    if (!c.cli.isSet(c.screenshot)) {
      std::fprintf(stderr,
                   "tocdlab-gui: error: no display (neither DISPLAY nor WAYLAND_DISPLAY is set); run it in a "
                   "desktop session, or save the demo as a picture without one: tocdlab-gui --demo "
                   "--screenshot FILE.png\n");
      return 1;
    }
    // A picture needs no screen: the demo renders offscreen.
    qputenv("QT_QPA_PLATFORM", "offscreen");
  }
  return run_window(argc, argv, c);
}
