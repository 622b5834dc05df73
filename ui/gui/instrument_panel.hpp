#pragma once

#include <QGroupBox>

class QLabel;

namespace tocd::gui {

class StatusLamp;

/// One instrument at a glance: connection state, identity, live value with its unit, and a
/// fault indicator with the last fault's text.
class InstrumentPanel : public QGroupBox {
  Q_OBJECT

 public:
  enum class Connection { absent, connecting, connected, lost };

  explicit InstrumentPanel(const QString& name, QWidget* parent = nullptr);

  void set_connection(Connection state, const QString& detail = {});
  void set_identity(const QString& vendor, const QString& model, const QString& serial,
                    const QString& firmware);
  /// Shows the live reading; several quantities (position and load) go in as several lines.
  void set_value(const QString& quantity, double value, const QString& unit, int precision = 4);
  void set_fault(bool fault, const QString& text = {});

  Connection connection() const noexcept { return connection_; }
  bool fault() const noexcept { return fault_; }
  QString identity_text() const;
  QString value_text() const;
  QString fault_text() const;

 private:
  Connection connection_ = Connection::absent;
  bool fault_ = false;
  StatusLamp* connection_lamp_;
  QLabel* connection_label_;
  QLabel* identity_label_;
  QLabel* value_label_;
  StatusLamp* fault_lamp_;
  QLabel* fault_label_;
  QStringList value_lines_;
  QStringList value_keys_;
};

}  // namespace tocd::gui
