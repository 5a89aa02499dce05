#include "reconfigure_section.h"

#include <dynamic_reconfigure/Reconfigure.h>

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

namespace ar_overlay {
namespace {

constexpr int kSliderSteps = 1000;

// A slider is only useful for a range a person can sweep (HSI bounds, gates);
// noise densities spanning 1e-9..1 get the spin box alone.
bool WantsSlider(const ParamSpec& p) {
  if (p.kind == ParamKind::kBool || !std::isfinite(p.max - p.min) || !(p.max > p.min)) return false;
  return p.min > 0.0 ? p.max / p.min <= 1e4 : p.max - p.min <= 1e4;
}

}  // namespace

ReconfigureSection::ReconfigureSection(const QString& title, QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  auto* heading = new QLabel("<b>" + title + "</b>");
  status_ = new QLabel("not connected");
  status_->setWordWrap(true);
  content_ = new QWidget;
  form_ = new QVBoxLayout(content_);
  form_->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(heading);
  layout->addWidget(status_);
  layout->addWidget(content_);
}

void ReconfigureSection::SetServer(const std::string& server_ns) {
  if (server_ns == server_ && (server_.empty() || description_sub_)) return;
  server_ = server_ns;
  description_sub_.shutdown();
  update_sub_.shutdown();
  client_.shutdown();
  Clear();
  if (server_.empty()) {
    status_->setText("not connected");
    return;
  }
  status_->setText(QString::fromStdString("waiting for " + server_ + "/parameter_descriptions"));
  description_sub_ = nh_.subscribe(server_ + "/parameter_descriptions", 1, &ReconfigureSection::OnDescription, this);
  update_sub_ = nh_.subscribe(server_ + "/parameter_updates", 1, &ReconfigureSection::OnUpdate, this);
  client_ = nh_.serviceClient<dynamic_reconfigure::Reconfigure>(server_ + "/set_parameters");
}

void ReconfigureSection::Clear() {
  setters_.clear();
  while (QLayoutItem* item = form_->takeAt(0)) {
    delete item->widget();
    delete item;
  }
}

void ReconfigureSection::OnDescription(const dynamic_reconfigure::ConfigDescription& description) {
  Clear();
  std::vector<std::string> skipped;
  int shown = 0;
  for (const ParamGroupSpec& group : GroupsFromDescription(description, &skipped)) {
    if (!groups_.empty() && std::find(groups_.begin(), groups_.end(), group.name) == groups_.end()) continue;
    auto* box = new QGroupBox(QString::fromStdString(group.name));
    auto* rows = new QFormLayout(box);
    rows->setContentsMargins(4, 2, 4, 2);
    for (const ParamSpec& p : group.params) {
      QWidget* editor = MakeEditor(p);
      editor->setToolTip(QString::fromStdString(p.description));
      rows->addRow(QString::fromStdString(p.name), editor);
      ++shown;
    }
    form_->addWidget(box);
  }
  QString text = QString("%1: %2 parameters").arg(QString::fromStdString(server_)).arg(shown);
  if (!skipped.empty()) text += QString(" (%1 of an unknown type not shown)").arg(skipped.size());
  status_->setText(text);
  OnUpdate(description.dflt);  // until the first parameter_updates, whose latched copy follows
}

void ReconfigureSection::OnUpdate(const dynamic_reconfigure::Config& config) {
  updating_ = true;
  for (auto& [name, set] : setters_) set(config);
  updating_ = false;
}

QWidget* ReconfigureSection::MakeEditor(const ParamSpec& spec) {
  if (spec.kind == ParamKind::kBool) {
    auto* box = new QCheckBox;
    box->setObjectName(QString::fromStdString(spec.name));
    connect(box, &QCheckBox::toggled, this, [this, spec](bool on) {
      if (!updating_) Send(spec, on ? 1.0 : 0.0);
    });
    setters_[spec.name] = [box, name = spec.name](const dynamic_reconfigure::Config& c) {
      double v = 0;
      if (!NumberFromConfig(c, name, &v)) return;
      const QSignalBlocker block(box);
      box->setChecked(v != 0.0);
    };
    return box;
  }
  if (spec.kind == ParamKind::kString) {
    auto* edit = new QLineEdit;
    edit->setObjectName(QString::fromStdString(spec.name));
    connect(edit, &QLineEdit::editingFinished, this, [this, spec, edit] { Send(spec, edit->text().toStdString()); });
    setters_[spec.name] = [edit, name = spec.name](const dynamic_reconfigure::Config& c) {
      std::string v;
      if (StringFromConfig(c, name, &v) && !edit->hasFocus()) edit->setText(QString::fromStdString(v));
    };
    return edit;
  }
  auto* row = new QWidget;
  auto* h = new QHBoxLayout(row);
  h->setContentsMargins(0, 0, 0, 0);
  auto* spin = new QDoubleSpinBox;
  spin->setObjectName(QString::fromStdString(spec.name));  // found by name in tests
  spin->setRange(spec.min, spec.max);
  spin->setDecimals(spec.kind == ParamKind::kInt ? 0 : (spec.max - spec.min > 10.0 ? 3 : 6));
  spin->setStepType(QAbstractSpinBox::AdaptiveDecimalStepType);
  spin->setKeyboardTracking(false);  // send on Enter or focus out, not per keystroke
  QSlider* slider = nullptr;
  if (WantsSlider(spec)) {
    slider = new QSlider(Qt::Horizontal);
    slider->setRange(0, kSliderSteps);
    h->addWidget(slider, 1);
  }
  h->addWidget(spin);
  const auto to_slider = [spec](double v) {
    return static_cast<int>(std::lround(kSliderSteps * (v - spec.min) / (spec.max - spec.min)));
  };
  connect(spin, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this, spec, slider, to_slider](double v) {
    if (slider) {
      const QSignalBlocker block(slider);
      slider->setValue(to_slider(v));
    }
    if (!updating_) Send(spec, v);
  });
  if (slider) {
    // While dragging only the spin box follows; the value is sent on release, so
    // the server (and the tracker's colour table, rebuilt per change) sees one
    // change, not hundreds. Clicks and keys on the slider send at once.
    connect(slider, &QSlider::valueChanged, this, [spec, slider, spin](int s) {
      const double v = spec.min + (spec.max - spec.min) * s / kSliderSteps;
      if (slider->isSliderDown()) {
        const QSignalBlocker block(spin);
        spin->setValue(v);
      } else {
        spin->setValue(v);
      }
    });
    connect(slider, &QSlider::sliderReleased, this, [this, spec, spin] {
      if (!updating_) Send(spec, spin->value());
    });
  }
  setters_[spec.name] = [spin, slider, name = spec.name, to_slider](const dynamic_reconfigure::Config& c) {
    double v = 0;
    if (!NumberFromConfig(c, name, &v)) return;
    const QSignalBlocker block(spin);
    spin->setValue(v);
    if (slider && !slider->isSliderDown()) {
      const QSignalBlocker block_slider(slider);
      slider->setValue(to_slider(v));
    }
  };
  return row;
}

bool ReconfigureSection::Send(const ParamSpec& spec, double value) {
  return Call(SingleParameter(spec, value), spec.name);
}

bool ReconfigureSection::Send(const ParamSpec& spec, const std::string& value) {
  return Call(SingleParameter(spec, value), spec.name);
}

bool ReconfigureSection::Call(const dynamic_reconfigure::Config& request, const std::string& name) {
  dynamic_reconfigure::Reconfigure srv;
  srv.request.config = request;
  // A dead server fails at once (no connection); a live one answers in
  // milliseconds, so the GUI thread is not held up.
  if (!client_ || !client_.call(srv)) {
    status_->setText(QString::fromStdString("could not set " + name + ": " + server_ + "/set_parameters failed"));
    ROS_WARN_THROTTLE(2.0, "tracking panel: %s/set_parameters failed for %s", server_.c_str(), name.c_str());
    return false;
  }
  OnUpdate(srv.response.config);  // the server may have clamped the value
  return true;
}

}  // namespace ar_overlay
