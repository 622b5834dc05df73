#pragma once

#include <QMainWindow>
#include <functional>
#include <memory>
#include <optional>

#include "gui_settings.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/mocks/simulated_lab.hpp"

class QAction;
class QTabWidget;

namespace tocd::gui {

class BrowserView;
class LabBackend;
class LabView;
class RunBackend;
class RunBrowserBackend;
class RunView;
class SimulationView;
class StudyBackend;

/// The workbench window. It only shows and commands: every decision is made by the
/// acquisition engine, the database, the drivers and the simulator it drives, exactly as
/// the `tocdlab` command line drives them.
class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  /// Which file a command asks for.
  enum class FileRequest { lab_config, protocol, record_database, open_database, open_server, export_csv };
  /// Asks the user for a path (a file dialog by default; open_server: a postgresql:// URI typed
  /// in); empty = cancelled.
  using FileChooser = std::function<QString(FileRequest)>;
  /// Makes the step predictor of a new run (default: the simulator with the photon budget of
  /// the simulation view; null = record without predictions).
  using PredictorFactory = std::function<std::shared_ptr<acquisition::StepPredictor>()>;

  struct Actions {
    QAction* open_lab = nullptr;
    QAction* simulated_lab = nullptr;
    QAction* disconnect_lab = nullptr;
    QAction* open_protocol = nullptr;
    QAction* choose_record_database = nullptr;
    QAction* start = nullptr;
    QAction* pause = nullptr;
    QAction* resume = nullptr;
    QAction* abort = nullptr;
    QAction* open_database = nullptr;
    QAction* open_server = nullptr;  // a lab's PostgreSQL server (docs/database.md)
    QAction* export_csv = nullptr;
    QAction* predict = nullptr;
    QAction* run_study = nullptr;
    QAction* quit = nullptr;
  };

  explicit MainWindow(QWidget* parent = nullptr);
  /// With explicit settings (tests use a temporary INI file).
  explicit MainWindow(std::unique_ptr<GuiSettings> settings, QWidget* parent = nullptr);
  ~MainWindow() override;

  const Actions& actions() const noexcept { return actions_; }
  void set_file_chooser(FileChooser chooser) { choose_file_ = std::move(chooser); }
  void set_predictor_factory(PredictorFactory factory) { predictor_factory_ = std::move(factory); }
  /// Options of the simulated lab started by the "Simulated lab" action.
  void set_simulated_lab_options(const mocks::SimulatedLabOptions& options) { sim_options_ = options; }
  mocks::SimulatedLabOptions simulated_lab_options() const { return sim_options_; }
  /// The simulated sample's truth (`tocdlab-gui --truth-*`): the stiffness and clearing of the
  /// sample the "Simulated lab" action prepares, and its relaxation and delayed clearing (set in
  /// the simulated lab options too).
  void set_sample_truth(const mocks::SampleTruth& truth);
  const mocks::SampleTruth& sample_truth() const noexcept { return sample_truth_; }

  /// Loads a protocol from TOML text (what "Open protocol" does after reading the file).
  bool load_protocol_text(const QString& text, const QString& source_name);
  bool load_protocol_file(const QString& path);
  void set_record_database(const QString& path);
  QString record_database() const { return record_db_path_; }
  const std::optional<acquisition::Protocol>& protocol() const noexcept { return protocol_; }

  LabBackend* lab_backend() const noexcept { return lab_; }
  RunBackend* run_backend() const noexcept { return run_; }
  RunBrowserBackend* browser_backend() const noexcept { return browser_; }
  StudyBackend* study_backend() const noexcept { return study_; }
  LabView* lab_view() const noexcept { return lab_view_; }
  RunView* run_view() const noexcept { return run_view_; }
  BrowserView* browser_view() const noexcept { return browser_view_; }
  SimulationView* simulation_view() const noexcept { return sim_view_; }
  QTabWidget* tabs() const noexcept { return tabs_; }

  /// The last error shown in a dialog ("" when none) and how many were shown.
  QString last_error() const { return last_error_; }
  int error_count() const noexcept { return error_count_; }

 signals:
  void lab_ready();
  void run_started(qint64 run_id);
  void run_finished(tocd::acquisition::EngineState state);

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  void build_actions();
  void build_views();
  void connect_backends();
  void wire_lab_signals();
  void wire_run_signals();
  void wire_browser_signals();
  void wire_simulation_signals();
  void update_actions();
  void show_error(const QString& action, const QString& message);
  QString ask_file(FileRequest request);

  // Commands (one per action).
  void open_lab();
  void start_simulated_lab();
  void open_protocol();
  void choose_record_database();
  void start_run();
  void open_database();
  void open_server_database();
  void export_csv();
  void predict_one();
  void run_study();

  std::unique_ptr<GuiSettings> settings_;
  Actions actions_;
  FileChooser choose_file_;
  PredictorFactory predictor_factory_;
  mocks::SimulatedLabOptions sim_options_;
  mocks::SampleTruth sample_truth_;
  std::optional<acquisition::Protocol> protocol_;
  QString record_db_path_;
  QString last_error_;
  int error_count_ = 0;
  bool lab_busy_ = false;

  LabBackend* lab_ = nullptr;
  RunBackend* run_ = nullptr;
  RunBrowserBackend* browser_ = nullptr;
  StudyBackend* study_ = nullptr;
  QTabWidget* tabs_ = nullptr;
  LabView* lab_view_ = nullptr;
  RunView* run_view_ = nullptr;
  BrowserView* browser_view_ = nullptr;
  SimulationView* sim_view_ = nullptr;
};

}  // namespace tocd::gui
