#include "skeleton_view.h"

#include <cmath>
#include <cstddef>
#include <memory>

#include <QMouseEvent>
#include <QOffscreenSurface>
#include <QOpenGLBuffer>
#include <QOpenGLContext>
#include <QOpenGLExtraFunctions>
#include <QOpenGLShaderProgram>
#include <QOpenGLVertexArrayObject>
#include <QOpenGLWidget>
#include <QPainter>
#include <QSurfaceFormat>
#include <QVBoxLayout>
#include <QWheelEvent>

namespace motionmap::studio {

namespace {

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 color;
uniform mat4 mvp;
out vec3 v_normal;
out vec3 v_color;
void main() {
  v_normal = normal;
  v_color = color;
  gl_Position = mvp * vec4(position, 1.0);
})";

const char* kFragmentShader = R"(#version 330 core
in vec3 v_normal;
in vec3 v_color;
uniform bool lit;
out vec4 frag;
void main() {
  vec3 c = v_color;
  if (lit) {
    vec3 n = normalize(v_normal);
    float key = max(dot(n, normalize(vec3(0.4, 0.9, 0.5))), 0.0);
    float fill = max(dot(n, normalize(vec3(-0.6, 0.2, -0.4))), 0.0);
    c = v_color * (0.3 + 0.6 * key + 0.25 * fill);
  }
  frag = vec4(c, 1.0);
})";

/// Whether this platform gives an OpenGL context (the offscreen platform does not; a window
/// holding a QOpenGLWidget there crashes in Qt 6.4, so the view falls back to QPainter).
bool openGlAvailable() {
  QOpenGLContext probe;
  return probe.create() && probe.isValid();
}

double gridStep(double extent) {
  return std::pow(10.0, std::floor(std::log10(extent * 0.5)));
}

}  // namespace

/// The OpenGL drawing of a SkeletonView's scene: everything but GL state lives in the parent.
class SkeletonCanvas : public QOpenGLWidget, protected QOpenGLExtraFunctions {
 public:
  explicit SkeletonCanvas(SkeletonView* view) : QOpenGLWidget(view), m_view(view) {}
  ~SkeletonCanvas() override {
    cleanupGL();
    // QOpenGLWidget's destructor destroys the context after this object stopped being a canvas.
    if (context()) disconnect(context(), nullptr, this, nullptr);
  }
  bool ready() const { return m_ready; }
  QString description() const { return m_description; }

 protected:
  void initializeGL() override;
  void paintGL() override;

 private:
  void cleanupGL();
  void drawVertices(const std::vector<MeshVertex>& vertices, GLenum mode, bool lit);

  SkeletonView* m_view;
  bool m_ready = false;
  QString m_description;
  std::unique_ptr<QOpenGLShaderProgram> m_program;
  QOpenGLVertexArrayObject m_vao;
  QOpenGLBuffer m_vbo{QOpenGLBuffer::VertexBuffer};
};

void SkeletonCanvas::initializeGL() {
  initializeOpenGLFunctions();
  const QSurfaceFormat format = context()->format();
  m_description =
      QString("OpenGL %1.%2 %3 · %4 · %5")
          .arg(format.majorVersion())
          .arg(format.minorVersion())
          .arg(format.profile() == QSurfaceFormat::CoreProfile ? "core" : "compatibility")
          .arg(reinterpret_cast<const char*>(glGetString(GL_RENDERER)))
          .arg(reinterpret_cast<const char*>(glGetString(GL_VERSION)));
  connect(context(), &QOpenGLContext::aboutToBeDestroyed, this, &SkeletonCanvas::cleanupGL);
  m_program = std::make_unique<QOpenGLShaderProgram>();
  if (!m_program->addShaderFromSourceCode(QOpenGLShader::Vertex, kVertexShader) ||
      !m_program->addShaderFromSourceCode(QOpenGLShader::Fragment, kFragmentShader) ||
      !m_program->link()) {
    qWarning("SkeletonView: shader error: %s", qPrintable(m_program->log()));
    m_program.reset();
    return;
  }
  m_vao.create();
  m_vbo.create();
  m_vbo.setUsagePattern(QOpenGLBuffer::DynamicDraw);
  m_vao.bind();
  m_vbo.bind();
  const auto stride = GLsizei(sizeof(MeshVertex));
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<void*>(offsetof(MeshVertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<void*>(offsetof(MeshVertex, normal)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<void*>(offsetof(MeshVertex, color)));
  m_vao.release();
  m_ready = true;
}

void SkeletonCanvas::cleanupGL() {
  if (!m_ready) return;
  makeCurrent();
  m_vbo.destroy();
  m_vao.destroy();
  m_program.reset();
  m_ready = false;
  doneCurrent();
}

void SkeletonCanvas::drawVertices(const std::vector<MeshVertex>& vertices, GLenum mode, bool lit) {
  if (vertices.empty()) return;
  m_program->setUniformValue("lit", lit);
  m_vbo.bind();
  m_vbo.allocate(vertices.data(), int(vertices.size() * sizeof(MeshVertex)));
  glDrawArrays(mode, 0, GLsizei(vertices.size()));
}

void SkeletonCanvas::paintGL() {
  glClearColor(0.93f, 0.94f, 0.96f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (!m_ready || !m_program) return;
  glEnable(GL_DEPTH_TEST);
  const OrbitCamera& camera = m_view->camera();
  m_program->bind();
  m_program->setUniformValue("mvp", camera.projection(size()) * camera.view());
  m_vao.bind();
  drawVertices(gridLines(camera.target, gridStep(m_view->extent())), GL_LINES, false);
  const WorldPose& world = m_view->worldPose();
  if (!world.positions.empty()) {
    drawVertices(skeletonMesh(boneSegments(m_view->skeleton(), world), world, m_view->extent()),
                 GL_TRIANGLES, true);
  }
  m_vao.release();
  m_program->release();
}

void SkeletonView::installSurfaceFormat() {
  QSurfaceFormat format;
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setDepthBufferSize(24);
  format.setSamples(4);
  QSurfaceFormat::setDefaultFormat(format);
}

SkeletonView::SkeletonView(QWidget* parent) : QWidget(parent) {
  setMinimumSize(200, 200);
  setFocusPolicy(Qt::ClickFocus);
  if (openGlAvailable()) {
    m_canvas = new SkeletonCanvas(this);
    // Mouse events fall through the canvas (it ignores them) to this widget.
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->addWidget(m_canvas);
  }
}

SkeletonView::~SkeletonView() = default;

bool SkeletonView::glReady() const {
  return m_canvas && m_canvas->ready();
}

QString SkeletonView::glDescription() const {
  return m_canvas ? m_canvas->description() : QString();
}

QImage SkeletonView::renderImage() {
  return m_canvas ? m_canvas->grabFramebuffer() : grab().toImage();
}

void SkeletonView::refresh() {
  if (m_canvas) m_canvas->update();
  update();
}

void SkeletonView::setSkeleton(const Skeleton& skeleton, bool keepCamera) {
  m_skeleton = skeleton;
  m_pose = Motion{};
  m_world = WorldPose{};
  Motion rest;
  rest.resize(1, skeleton.num_joints());
  for (int j = 0; j < skeleton.num_joints(); ++j)
    rest.translation(0, j) = skeleton.joints[std::size_t(j)].offset;
  m_extent = poseExtent(forward_kinematics(skeleton, rest, 0));
  if (!keepCamera) {
    m_camera = OrbitCamera{};
    m_camera.distance = 1.7 * m_extent;
    m_hasTarget = false;
  }
  refresh();
}

void SkeletonView::setPose(const Motion& motion, int frame) {
  if (motion.num_joints != m_skeleton.num_joints() || frame < 0 || frame >= motion.num_frames)
    return;
  m_pose.frame_time = motion.frame_time;
  m_pose.resize(1, motion.num_joints);
  const PoseView pose = motion.pose(frame);
  std::copy(pose.rotations.begin(), pose.rotations.end(), m_pose.rotations.begin());
  std::copy(pose.translations.begin(), pose.translations.end(), m_pose.translations.begin());
  forward_kinematics(m_skeleton, m_pose.pose(0), m_world);
  // Follow the root horizontally, keep the look-at height at the body's middle.
  if (m_followRoot || !m_hasTarget) {
    const Eigen::Vector3d root = m_world.positions[std::size_t(motion_root(m_skeleton, motion))];
    m_camera.target = Eigen::Vector3d(root.x(), 0.45 * m_extent, root.z());
    m_hasTarget = true;
  }
  emit poseChanged();
  refresh();
}

void SkeletonView::setFollowRoot(bool follow) {
  m_followRoot = follow;
  refresh();
}

std::vector<QPointF> SkeletonView::jointPixels() const {
  std::vector<QPointF> out;
  for (const auto& p : m_world.positions) out.push_back(projectToPixels(m_camera, size(), p));
  return out;
}

void SkeletonView::paintEvent(QPaintEvent*) {
  if (m_canvas) return;
  // Without OpenGL: the same scene as lines, far bones first.
  QPainter painter(this);
  painter.setRenderHint(QPainter::Antialiasing);
  painter.fillRect(rect(), QColor::fromRgbF(0.93f, 0.94f, 0.96f));
  const auto grid = gridLines(m_camera.target, gridStep(m_extent));
  painter.setPen(QPen(QColor(150, 150, 150), 1));
  for (std::size_t i = 0; i + 1 < grid.size(); i += 2) {
    const auto p = [&](const MeshVertex& v) {
      return projectToPixels(m_camera, size(),
                             Eigen::Vector3d(v.position[0], v.position[1], v.position[2]));
    };
    painter.drawLine(p(grid[i]), p(grid[i + 1]));
  }
  painter.setPen(QPen(QColor(200, 180, 140), 5, Qt::SolidLine, Qt::RoundCap));
  for (const auto& bone : boneSegments(m_skeleton, m_world)) {
    painter.drawLine(projectToPixels(m_camera, size(), bone.from),
                     projectToPixels(m_camera, size(), bone.to));
  }
  painter.setPen(Qt::NoPen);
  painter.setBrush(QColor(64, 115, 217));
  for (const QPointF& p : jointPixels()) painter.drawEllipse(p, 3.5, 3.5);
}

void SkeletonView::resizeEvent(QResizeEvent*) {
  refresh();
}

void SkeletonView::mousePressEvent(QMouseEvent* event) {
  m_lastMouse = event->position().toPoint();
}

void SkeletonView::mouseMoveEvent(QMouseEvent* event) {
  const QPoint p = event->position().toPoint();
  const QPoint d = p - m_lastMouse;
  m_lastMouse = p;
  if (event->buttons() & Qt::LeftButton) {
    m_camera.orbit(d.x(), d.y());
  } else if (event->buttons() & (Qt::MiddleButton | Qt::RightButton)) {
    m_camera.panBy(d.x(), d.y(), size());
  } else {
    return;
  }
  refresh();
}

void SkeletonView::wheelEvent(QWheelEvent* event) {
  m_camera.zoom(event->angleDelta().y() / 120.0);
  refresh();
}

}  // namespace motionmap::studio
