#pragma once

#include <QObject>
#include <QString>
#include <QThreadPool>
#include <exception>
#include <functional>
#include <memory>

#include "tocd/core/thread_priority.hpp"

namespace tocd::gui {

/// Runs blocking work (database queries, exports, simulations) off the GUI thread and
/// delivers the result, or the error text, back on the thread of this object through a
/// queued call, so the window never freezes and never touches widgets from a worker.
///
/// The destructor waits for work still running; a result that arrives after this object
/// is gone is dropped by Qt together with the queued call.
class TaskRunner : public QObject {
  Q_OBJECT

 public:
  /// `background`: the work is computation (studies, fits) that may run beside a recording;
  /// each task runs at the background niceness (tocd::run_this_thread_in_background), and the
  /// threads it starts inherit it, so that it never costs the instruments' pollers a reading.
  explicit TaskRunner(QObject* parent = nullptr, int max_threads = 1, bool background = false);
  ~TaskRunner() override;

  template <class T>
  void run(std::function<T()> work, std::function<void(T&)> done,
           std::function<void(const QString&)> failed) {
    ++in_flight_;
    pool_.start([this, work = std::move(work), done = std::move(done), failed = std::move(failed)]() mutable {
      if (background_) run_this_thread_in_background();
      try {
        auto result = std::make_shared<T>(work());
        QMetaObject::invokeMethod(
            this,
            [this, result, done = std::move(done)] {
              --in_flight_;
              done(*result);
            },
            Qt::QueuedConnection);
      } catch (const std::exception& e) {
        deliver_failure(std::move(failed), QString::fromUtf8(e.what()));
      } catch (...) {
        deliver_failure(std::move(failed), QStringLiteral("unknown error"));
      }
    });
  }

  /// Work started and not yet delivered.
  int in_flight() const noexcept { return in_flight_; }
  /// Blocks until every started task has finished running (results may still be queued).
  void wait();

 private:
  void deliver_failure(std::function<void(const QString&)> failed, const QString& message);

  QThreadPool pool_;
  bool background_ = false;
  int in_flight_ = 0;  ///< touched only on this object's thread
};

}  // namespace tocd::gui
