#include "canvas.hpp"

#include <QFile>
#include <QGuiApplication>
#include <QImage>
#include <QSvgGenerator>
#include <algorithm>
#include <cctype>
#include <string>
#include <system_error>

#include "tocd/core/error.hpp"
#include "tocd/core/runtime_dir.hpp"

namespace tocd::plot {

ImageFormat image_format_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".png") return ImageFormat::png;
  if (ext == ".svg") return ImageFormat::svg;
  throw ConfigError("output file '" + path.string() + "': the extension must be .png or .svg");
}

namespace detail {

// Text needs Qt's font database, which needs a QGuiApplication. The offscreen platform is
// forced: the figures are never shown, and a missing or unreachable display must not matter.
void ensure_gui_application() {
  if (QCoreApplication::instance() != nullptr) return;
  qputenv("QT_QPA_PLATFORM", "offscreen");
  ensure_runtime_dir();  // else Qt warns about XDG_RUNTIME_DIR on every figure as root
  static int argc = 1;
  static char name[] = "tocdlab";
  static char* argv[] = {name, nullptr};
  static QGuiApplication* app = new QGuiApplication(argc, argv);  // lives until exit
  (void)app;
}

QFont figure_font() {
  ensure_gui_application();
  QFont f = QGuiApplication::font();
  f.setPixelSize(12);
  return f;
}

void render_to_file(const std::filesystem::path& path, FigureSize size,
                    const std::function<void(QPainter&)>& paint) {
  if (size.width < 200 || size.height < 150 || size.width > 20000 || size.height > 20000)
    throw ConfigError("figure size " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                      " is out of range: accepted 200x150 to 20000x20000");
  const ImageFormat format = image_format_of(path);
  ensure_gui_application();
  // Written beside the target and renamed over it: a reader never sees half a picture.
  const std::filesystem::path tmp = path.string() + ".part";
  const QString qtmp = QString::fromStdString(tmp.string());
  bool ok = false;
  if (format == ImageFormat::png) {
    QImage image(size.width, size.height, QImage::Format_RGB32);
    image.fill(qcolour(kBackgroundColour));
    {
      QPainter p(&image);
      p.setRenderHint(QPainter::Antialiasing, true);
      p.setFont(figure_font());
      paint(p);
    }
    ok = image.save(qtmp, "PNG");
  } else {
    QSvgGenerator svg;
    svg.setFileName(qtmp);
    svg.setSize(QSize(size.width, size.height));
    svg.setViewBox(QRect(0, 0, size.width, size.height));
    svg.setTitle(QStringLiteral("tocdlab figure"));
    QPainter p;
    if (p.begin(&svg)) {
      p.fillRect(QRectF(0, 0, size.width, size.height), qcolour(kBackgroundColour));
      p.setFont(figure_font());
      paint(p);
      ok = p.end();
    }
    ok = ok && QFile::exists(qtmp);
  }
  std::error_code ec;
  if (ok) std::filesystem::rename(tmp, path, ec);
  if (!ok || ec) {
    std::filesystem::remove(tmp, ec);
    throw Error("cannot write figure '" + path.string() + "' (is the folder there and writable?)");
  }
}

}  // namespace detail
}  // namespace tocd::plot
