#include "background.hpp"

namespace tocd::gui {

TaskRunner::TaskRunner(QObject* parent, int max_threads, bool background)
    : QObject(parent), background_(background) {
  pool_.setMaxThreadCount(max_threads);
}

TaskRunner::~TaskRunner() {
  pool_.waitForDone();
}

void TaskRunner::wait() {
  pool_.waitForDone();
}

void TaskRunner::deliver_failure(std::function<void(const QString&)> failed, const QString& message) {
  QMetaObject::invokeMethod(
      this,
      [this, failed = std::move(failed), message] {
        --in_flight_;
        if (failed) failed(message);
      },
      Qt::QueuedConnection);
}

}  // namespace tocd::gui
