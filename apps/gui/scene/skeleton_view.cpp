#include "scene/skeleton_view.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>

#include <QKeyEvent>
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
#include <QToolTip>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <limits>

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
uniform float alpha;
out vec4 frag;
void main() {
  vec3 c = v_color;
  if (lit) {
    vec3 n = normalize(v_normal);
    float key = max(dot(n, normalize(vec3(0.4, 0.9, 0.5))), 0.0);
    float fill = max(dot(n, normalize(vec3(-0.6, 0.2, -0.4))), 0.0);
    c = v_color * (0.4 + 0.55 * key + 0.25 * fill);  // no black sides: bones stay their colour
  }
  frag = vec4(c, alpha);
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

const Eigen::Vector3f kBackground(0.93f, 0.94f, 0.96f);

/// The opacity of an overlaid character (setOverlay).
constexpr double kOverlayOpacity = 0.6;

/// The hovered joint's name: dark text on a light rounded box beside the joint.
void drawLabel(QPainter& painter, QPointF at, const QString& text) {
  if (text.isEmpty()) return;
  const QFontMetricsF metrics(painter.font());
  QRectF box(at + QPointF(10, -metrics.height() - 6), metrics.size(0, text) + QSizeF(10, 4));
  painter.setPen(QColor(90, 90, 90));
  painter.setBrush(QColor(255, 255, 255, 220));
  painter.drawRoundedRect(box, 3, 3);
  painter.setPen(QColor(20, 20, 20));
  painter.drawText(box, Qt::AlignCenter, text);
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
  glClearColor(kBackground.x(), kBackground.y(), kBackground.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (!m_ready || !m_program) return;
  glEnable(GL_DEPTH_TEST);
  const OrbitCamera& camera = m_view->camera();
  m_program->bind();
  m_program->setUniformValue("mvp", camera.projection(size()) * camera.view());
  m_program->setUniformValue("alpha", 1.0f);
  m_vao.bind();
  drawVertices(gridLines(camera.target, gridStep(m_view->extent())), GL_LINES, false);
  const WorldPose& world = m_view->worldPose();
  if (!world.positions.empty()) {
    const std::vector<BoneSegment> bones = m_view->bones();
    // The shadow darkens what is under it to at most its own shade (GL_MIN): overlapping strips
    // do not add up, the grid's darker lines stay. No depth writes: it lies on the floor.
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    glDepthMask(GL_FALSE);
    std::vector<BoneSegment> shadowed = bones;
    const std::vector<BoneSegment> overlay = m_view->overlayBones();
    shadowed.insert(shadowed.end(), overlay.begin(), overlay.end());
    drawVertices(shadowMesh(shadowed, m_view->extent(), 0.0, kBackground), GL_TRIANGLES, false);
    glDepthMask(GL_TRUE);
    glBlendEquation(GL_FUNC_ADD);
    glDisable(GL_BLEND);
    drawVertices(skeletonMesh(bones, world, m_view->extent(), m_view->sides(), m_view->body(),
                              m_view->selectedJoint()),
                 GL_TRIANGLES, true);
    drawVertices(trailMesh(m_view->trail(), m_view->extent()), GL_TRIANGLES, true);
  }
  if (m_view->hasOverlay()) {
    // The second character translucent: its depth first, then its colour blended where it is
    // nearest, so its own overlapping capsules blend once.
    const std::vector<MeshVertex> mesh = m_view->overlayMesh();
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    drawVertices(mesh, GL_TRIANGLES, true);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    m_program->setUniformValue("alpha", GLfloat(kOverlayOpacity));
    drawVertices(mesh, GL_TRIANGLES, true);
    m_program->setUniformValue("alpha", 1.0f);
    glDisable(GL_BLEND);
    glDepthFunc(GL_LESS);
  }
  m_vao.release();
  m_program->release();
  glDisable(GL_DEPTH_TEST);
  QPainter painter(this);
  m_view->paintOverlay(painter);
}

void SkeletonView::installSurfaceFormat() {
  QSurfaceFormat format;
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setDepthBufferSize(24);
  format.setSamples(4);
  QSurfaceFormat::setDefaultFormat(format);
}

/// setOverlay's character.
struct SkeletonView::Overlay {
  Skeleton skeleton;
  WorldPose world;
  std::vector<bool> detached;
  std::vector<bool> body;
  QColor color;
};

SkeletonView::SkeletonView(QWidget* parent) : QWidget(parent) {
  setMinimumSize(200, 200);
  setFocusPolicy(Qt::ClickFocus);
  setMouseTracking(true);  // hover names joints
  setToolTip(
      tr("3-D view: drag to orbit, right or middle drag to pan, wheel to zoom; hover a "
         "joint for its name, click it to select it; F frames the character, Home (here) "
         "resets the camera"));
  if (openGlAvailable()) {
    m_canvas = new SkeletonCanvas(this);
    m_canvas->setMouseTracking(true);
    // Mouse events fall through the canvas (it ignores them) to this widget.
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->addWidget(m_canvas);
  }
}

SkeletonView::~SkeletonView() = default;

void SkeletonView::setOverlay(const Skeleton& skeleton, const WorldPose& pose,
                              const std::vector<bool>& detached, const QColor& color) {
  if (pose.positions.size() != std::size_t(skeleton.num_joints())) return clearOverlay();
  if (!m_overlay) m_overlay = std::make_unique<Overlay>();
  m_overlay->skeleton = skeleton;
  m_overlay->detached = detached.size() == pose.positions.size()
                            ? detached
                            : std::vector<bool>(pose.positions.size(), false);
  m_overlay->body = body_joints(skeleton, m_overlay->detached);
  m_overlay->world = pose;
  m_overlay->color = color;
  refresh();
}

void SkeletonView::clearOverlay() {
  if (!m_overlay) return;
  m_overlay.reset();
  refresh();
}

const WorldPose& SkeletonView::overlayPose() const {
  static const WorldPose none;
  return m_overlay ? m_overlay->world : none;
}

QColor SkeletonView::overlayColor() const {
  return m_overlay ? m_overlay->color : QColor();
}

std::vector<BoneSegment> SkeletonView::overlayBones() const {
  if (!m_overlay) return {};
  return bone_segments(m_overlay->skeleton, m_overlay->world, m_overlay->detached);
}

std::vector<QPointF> SkeletonView::overlayJointPixels() const {
  std::vector<QPointF> out;
  if (!m_overlay) return out;
  for (const auto& p : m_overlay->world.positions)
    out.push_back(projectToPixels(m_camera, size(), p));
  return out;
}

std::vector<MeshVertex> SkeletonView::overlayMesh() const {
  if (!m_overlay) return {};
  // Translucent, each surface may be drawn once: coincident joints (one sphere, not several at
  // the same depth, blended twice) and bones of no length (spheres inside their joint's) dropped.
  const std::vector<Eigen::Vector3d>& at = m_overlay->world.positions;
  const double tiny = 1e-6 * m_extent;
  std::vector<bool> body = m_overlay->body;
  body.resize(at.size(), true);
  for (std::size_t j = 0; j < at.size(); ++j) {
    for (std::size_t k = 0; k < j && body[j]; ++k) {
      if (body[k] && (at[k] - at[j]).norm() <= tiny) body[j] = false;
    }
  }
  std::vector<BoneSegment> bones = overlayBones();
  std::erase_if(bones, [&](const BoneSegment& b) { return (b.to - b.from).norm() <= tiny; });
  std::vector<MeshVertex> mesh = skeletonMesh(bones, m_overlay->world, m_extent, {}, body);
  const QColor& c = m_overlay->color;
  for (MeshVertex& v : mesh) {
    v.color[0] = float(c.redF());
    v.color[1] = float(c.greenF());
    v.color[2] = float(c.blueF());
  }
  return mesh;
}

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
  m_motion.reset();
  m_detached.assign(std::size_t(skeleton.num_joints()), false);
  m_body = body_joints(skeleton, m_detached);
  m_sides = joint_sides(skeleton);
  m_bounds = MotionBounds{};
  m_root = skeleton.num_joints() > 0 ? skeleton.roots().front() : 0;
  m_hovered = -1;
  m_selected = -1;
  m_trail.clear();
  m_dragJoint = -1;
  m_dragTarget.reset();
  if (!keepCamera && !m_pinned.empty()) {
    m_pinned.clear();
    emit pinnedJointsChanged();
  }
  Motion rest;
  rest.resize(1, skeleton.num_joints());
  for (int j = 0; j < skeleton.num_joints(); ++j)
    rest.translation(0, j) = skeleton.joints[std::size_t(j)].offset;
  m_extent = pose_extent(forward_kinematics(skeleton, rest, 0));
  if (!keepCamera) {
    m_camera = OrbitCamera{};
    m_camera.distance = 1.7 * m_extent;
    m_followOffset = Eigen::Vector3d(0.0, 0.45 * m_extent, 0.0);
    m_hasTarget = false;
    m_autoFramed = false;
  }
  m_needsFraming = !keepCamera;
  emit skeletonChanged();
  emit selectedJointChanged(-1);
  refresh();
}

void SkeletonView::setMotion(const Motion& motion) {
  if (motion.num_joints != m_skeleton.num_joints() || motion.num_frames <= 0) return;
  // The window hands the motion over on every jump into the clip (a click on the map): the same
  // motion again needs no new bounds or trail.
  const auto same = [](const Motion& a, const Motion& b) {
    return a.num_frames == b.num_frames && a.frame_time == b.frame_time &&
           std::memcmp(a.rotations.data(), b.rotations.data(),
                       a.rotations.size() * sizeof(Eigen::Quaterniond)) == 0 &&
           std::memcmp(a.translations.data(), b.translations.data(),
                       a.translations.size() * sizeof(Eigen::Vector3d)) == 0;
  };
  if (m_motion && !m_needsFraming && same(*m_motion, motion)) return;
  m_motion = std::make_shared<const Motion>(motion);
  m_detached = detached_joints(m_skeleton, motion);
  m_body = body_joints(m_skeleton, m_detached);
  m_root = motion_root(m_skeleton, motion);
  m_bounds = motionBounds(m_skeleton, motion, m_body, m_root);
  if (m_selected >= 0) m_trail = jointTrail(m_skeleton, motion, m_selected);
  if (m_needsFraming) {
    m_needsFraming = false;
    resetCamera();
  }
  refresh();
}

Eigen::Vector3d SkeletonView::rootFloor() const {
  if (std::size_t(m_root) < m_world.positions.size()) {
    const Eigen::Vector3d& r = m_world.positions[std::size_t(m_root)];
    return {r.x(), 0.0, r.z()};
  }
  if (m_motion) {  // no pose yet: the first frame's
    const WorldPose first = forward_kinematics(m_skeleton, *m_motion, 0);
    const Eigen::Vector3d& r = first.positions[std::size_t(m_root)];
    return {r.x(), 0.0, r.z()};
  }
  return Eigen::Vector3d::Zero();
}

void SkeletonView::aim(const Eigen::Vector3d& center, double radius) {
  m_camera.pan.setZero();
  m_camera.target = center;
  m_frameRadius = radius > 0.0 && std::isfinite(radius) ? radius : 0.5 * m_extent;
  m_camera.distance = m_camera.fitDistance(m_frameRadius, size());
  if (m_followRoot) m_followOffset = center - rootFloor();
  m_hasTarget = true;
}

void SkeletonView::frameClip() {
  if (!m_bounds.valid) return frameCharacter();
  if (m_followRoot) {
    const Eigen::Vector3d c = 0.5 * (m_bounds.followMin + m_bounds.followMax);
    aim(rootFloor() + c, 0.5 * (m_bounds.followMax - m_bounds.followMin).norm());
  } else {
    aim(0.5 * (m_bounds.boxMin + m_bounds.boxMax),
        0.5 * (m_bounds.boxMax - m_bounds.boxMin).norm());
  }
  m_autoFramed = true;
  refresh();
}

void SkeletonView::frameCharacter() {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  const auto add = [&](const Eigen::Vector3d& p) {
    if (!p.allFinite()) return;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (std::size_t j = 0; j < m_world.positions.size(); ++j) {
    if (j < m_body.size() && m_body[j]) add(m_world.positions[j]);
  }
  for (const auto& e : m_world.end_sites) add(e);
  if (!lo.allFinite()) return;  // no pose shown
  aim(0.5 * (lo + hi), std::max(0.5 * (hi - lo).norm(), 0.05 * m_extent));
  m_autoFramed = false;
  refresh();
}

void SkeletonView::resetCamera() {
  m_camera.yaw = OrbitCamera::kDefaultYaw;
  m_camera.pitch = OrbitCamera::kDefaultPitch;
  frameClip();
}

void SkeletonView::applyCameraPreset(CameraPreset preset) {
  applyPreset(m_camera, preset);
  refresh();
}

void SkeletonView::setCamera(const OrbitCamera& camera) {
  m_camera = camera;
  m_autoFramed = false;
  if (m_followRoot) m_followOffset = camera.target - rootFloor();
  refresh();
}

std::vector<BoneSegment> SkeletonView::bones() const {
  return bone_segments(m_skeleton, m_world, m_detached);
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
  if (!m_motion) m_root = motion_root(m_skeleton, motion);
  // Following: the look-at point keeps its offset from the root's floor point.
  if (m_followRoot || !m_hasTarget) {
    m_camera.target = rootFloor() + m_followOffset;
    m_hasTarget = true;
  }
  emit poseChanged();
  refresh();
}

void SkeletonView::setFollowRoot(bool follow) {
  m_followRoot = follow;
  if (follow) m_followOffset = m_camera.target - rootFloor();  // no jump when turned on
  refresh();
}

std::vector<QPointF> SkeletonView::jointPixels() const {
  std::vector<QPointF> out;
  for (const auto& p : m_world.positions) out.push_back(projectToPixels(m_camera, size(), p));
  return out;
}

int SkeletonView::jointAt(QPointF pixel, double maxDistance) const {
  int best = -1;
  double bestDistance = maxDistance;
  const std::vector<QPointF> pixels = jointPixels();
  for (std::size_t j = 0; j < pixels.size(); ++j) {
    if (j < m_body.size() && !m_body[j]) continue;
    const double d = std::hypot(pixels[j].x() - pixel.x(), pixels[j].y() - pixel.y());
    if (d <= bestDistance) {  // NaN (behind the camera) never is
      bestDistance = d;
      best = int(j);
    }
  }
  return best;
}

void SkeletonView::setSelectedJoint(int joint) {
  if (joint < -1 || joint >= m_skeleton.num_joints()) joint = -1;
  if (joint == m_selected) return;
  m_selected = joint;
  m_trail = joint >= 0 && m_motion ? jointTrail(m_skeleton, *m_motion, joint)
                                   : std::vector<Eigen::Vector3d>{};
  emit selectedJointChanged(joint);
  refresh();
}

QString SkeletonView::hoverLabel(QPointF* at) const {
  if (m_hovered < 0 || std::size_t(m_hovered) >= m_world.positions.size()) return {};
  *at = projectToPixels(m_camera, size(), m_world.positions[std::size_t(m_hovered)]);
  return QString::fromStdString(m_skeleton.joints[std::size_t(m_hovered)].name);
}

void SkeletonView::paintEvent(QPaintEvent*) {
  if (m_canvas) return;
  QPainter painter(this);
  paintFallback(painter);
}

void SkeletonView::paintFallback(QPainter& painter) {
  // Without OpenGL: the same scene drawn by QPainter, far parts first.
  painter.setRenderHint(QPainter::Antialiasing);
  const QColor background = QColor::fromRgbF(kBackground.x(), kBackground.y(), kBackground.z());
  painter.fillRect(rect(), background);
  const auto pixel = [&](const Eigen::Vector3d& p) { return projectToPixels(m_camera, size(), p); };
  const auto grid = gridLines(m_camera.target, gridStep(m_extent));
  painter.setPen(QPen(QColor(150, 150, 150), 1));
  for (std::size_t i = 0; i + 1 < grid.size(); i += 2) {
    const auto p = [&](const MeshVertex& v) {
      return pixel(Eigen::Vector3d(v.position[0], v.position[1], v.position[2]));
    };
    painter.drawLine(p(grid[i]), p(grid[i + 1]));
  }
  const std::vector<BoneSegment> bones = this->bones();
  const std::vector<BoneSegment> overlayBones = this->overlayBones();
  const double radius = boneRadius(m_extent);
  const Eigen::Vector3d right = m_camera.right();
  const auto pixelRadius = [&](const Eigen::Vector3d& p, double r) {
    const QPointF a = pixel(p), b = pixel(p + right * r);
    return std::hypot(a.x() - b.x(), a.y() - b.y());
  };
  // The shadow: the bones' floor projections drawn opaque on a layer, blurred by scaling down
  // and back up, then laid over the floor translucent (overlaps do not darken twice).
  std::vector<BoneSegment> shadowed = bones;
  shadowed.insert(shadowed.end(), overlayBones.begin(), overlayBones.end());
  if (!shadowed.empty()) {
    QImage layer(size() / 4, QImage::Format_ARGB32_Premultiplied);
    layer.fill(Qt::transparent);
    {
      QPainter lp(&layer);
      lp.setRenderHint(QPainter::Antialiasing);
      lp.scale(0.25, 0.25);
      for (const BoneSegment& bone : shadowed) {
        const Eigen::Vector3d a(bone.from.x(), 0.0, bone.from.z()),
            b(bone.to.x(), 0.0, bone.to.z());
        const double fade =
            std::clamp(1.0 - std::min(bone.from.y(), bone.to.y()) / (1.5 * m_extent), 0.0, 1.0);
        lp.setPen(QPen(QColor(0, 0, 0, int(255 * fade)), 3.0 * pixelRadius(a, radius),
                       Qt::SolidLine, Qt::RoundCap));
        lp.drawLine(pixel(a), pixel(b));
      }
    }
    const QImage blurred =
        layer.scaled(layer.size() / 3, Qt::IgnoreAspectRatio, Qt::SmoothTransformation)
            .scaled(size(), Qt::IgnoreAspectRatio, Qt::SmoothTransformation);
    painter.setOpacity(0.4);
    painter.drawImage(0, 0, blurred);
    painter.setOpacity(1.0);
  }
  // Capsules and spheres, far to near; each shaded across its width like a lit cylinder.
  struct Item {
    double depth;
    int bone;   // index in bones, or −1 for a joint
    int joint;  // the joint for a sphere
  };
  std::vector<Item> items;
  const Eigen::Vector3d eye = m_camera.eye();
  for (std::size_t b = 0; b < bones.size(); ++b)
    items.push_back({(0.5 * (bones[b].from + bones[b].to) - eye).norm(), int(b), -1});
  for (std::size_t j = 0; j < m_world.positions.size(); ++j) {
    if (j < m_body.size() && !m_body[j]) continue;
    items.push_back({(m_world.positions[j] - eye).norm(), -1, int(j)});
  }
  std::sort(items.begin(), items.end(),
            [](const Item& a, const Item& b) { return a.depth > b.depth; });
  const auto qcolor = [](const Eigen::Vector3f& c, double k) {
    return QColor::fromRgbF(float(std::clamp(c.x() * k, 0.0, 1.0)),
                            float(std::clamp(c.y() * k, 0.0, 1.0)),
                            float(std::clamp(c.z() * k, 0.0, 1.0)));
  };
  const auto side = [&](int j) {
    return j >= 0 && std::size_t(j) < m_sides.size() ? m_sides[std::size_t(j)] : JointSide::Center;
  };
  for (const Item& item : items) {
    if (item.bone >= 0) {
      const BoneSegment& bone = bones[std::size_t(item.bone)];
      const QPointF a = pixel(bone.from), b = pixel(bone.to);
      const double w = 2.0 * std::max(pixelRadius(bone.from, radius), 1.5);
      QPointF normal(-(b - a).y(), (b - a).x());
      const double len = std::hypot(normal.x(), normal.y());
      normal = len > 0 ? normal * (0.5 * w / len) : QPointF(0, 0.5 * w);
      const Eigen::Vector3f c = side_color(side(bone.joint), true);
      QLinearGradient shade(a + normal, a - normal);
      shade.setColorAt(0.0, qcolor(c, 0.55));
      shade.setColorAt(0.35, qcolor(c, 1.1));
      shade.setColorAt(1.0, qcolor(c, 0.5));
      painter.setPen(QPen(QBrush(shade), w, Qt::SolidLine, Qt::RoundCap));
      painter.drawLine(a, b);
    } else {
      const QPointF p = pixel(m_world.positions[std::size_t(item.joint)]);
      const bool selected = item.joint == m_selected;
      const double r =
          pixelRadius(m_world.positions[std::size_t(item.joint)], radius * (selected ? 2.0 : 1.25));
      const Eigen::Vector3f c =
          selected ? Eigen::Vector3f(1.0f, 0.6f, 0.05f) : side_color(side(item.joint));
      QRadialGradient shade(p - QPointF(0.35 * r, 0.35 * r), 1.3 * std::max(r, 2.0));
      shade.setColorAt(0.0, qcolor(c, 1.3));
      shade.setColorAt(1.0, qcolor(c, 0.55));
      painter.setPen(Qt::NoPen);
      painter.setBrush(shade);
      painter.drawEllipse(p, std::max(r, 2.5), std::max(r, 2.5));
    }
  }
  // The overlaid character: its capsules and spheres far to near in its colour on a layer,
  // laid over the scene translucent (so its own overlaps do not darken).
  if (m_overlay) {
    QImage layer(size(), QImage::Format_ARGB32_Premultiplied);
    layer.fill(Qt::transparent);
    {
      QPainter lp(&layer);
      lp.setRenderHint(QPainter::Antialiasing);
      const WorldPose& world = m_overlay->world;
      std::vector<Item> ghost;
      for (std::size_t b = 0; b < overlayBones.size(); ++b)
        ghost.push_back(
            {(0.5 * (overlayBones[b].from + overlayBones[b].to) - eye).norm(), int(b), -1});
      for (std::size_t j = 0; j < world.positions.size(); ++j) {
        if (j < m_overlay->body.size() && !m_overlay->body[j]) continue;
        ghost.push_back({(world.positions[j] - eye).norm(), -1, int(j)});
      }
      std::sort(ghost.begin(), ghost.end(),
                [](const Item& a, const Item& b) { return a.depth > b.depth; });
      const QColor base = m_overlay->color;
      const Eigen::Vector3f c(float(base.redF()), float(base.greenF()), float(base.blueF()));
      for (const Item& item : ghost) {
        if (item.bone >= 0) {
          const BoneSegment& bone = overlayBones[std::size_t(item.bone)];
          const QPointF a = pixel(bone.from), b = pixel(bone.to);
          const double w = 2.0 * std::max(pixelRadius(bone.from, radius), 1.5);
          QPointF normal(-(b - a).y(), (b - a).x());
          const double len = std::hypot(normal.x(), normal.y());
          normal = len > 0 ? normal * (0.5 * w / len) : QPointF(0, 0.5 * w);
          QLinearGradient shade(a + normal, a - normal);
          shade.setColorAt(0.0, qcolor(c, 0.6));
          shade.setColorAt(0.35, qcolor(c, 1.15));
          shade.setColorAt(1.0, qcolor(c, 0.55));
          lp.setPen(QPen(QBrush(shade), w, Qt::SolidLine, Qt::RoundCap));
          lp.drawLine(a, b);
        } else {
          const Eigen::Vector3d& at = world.positions[std::size_t(item.joint)];
          const QPointF p = pixel(at);
          const double r = std::max(pixelRadius(at, radius * 1.25), 2.5);
          QRadialGradient shade(p - QPointF(0.35 * r, 0.35 * r), 1.3 * r);
          shade.setColorAt(0.0, qcolor(c, 1.3));
          shade.setColorAt(1.0, qcolor(c, 0.6));
          lp.setPen(Qt::NoPen);
          lp.setBrush(shade);
          lp.drawEllipse(p, r, r);
        }
      }
    }
    painter.setOpacity(kOverlayOpacity);
    painter.drawImage(0, 0, layer);
    painter.setOpacity(1.0);
  }
  // The selected joint's trail, red → blue over the clip.
  for (std::size_t i = 0; i + 1 < m_trail.size(); ++i) {
    const QPointF a = pixel(m_trail[i]), b = pixel(m_trail[i + 1]);
    if (!std::isfinite(a.x()) || !std::isfinite(b.x())) continue;
    painter.setPen(QPen(qcolor(trailColor(double(i) / double(m_trail.size() - 1)), 1.0), 2.0,
                        Qt::SolidLine, Qt::RoundCap));
    painter.drawLine(a, b);
  }
  paintOverlay(painter);
}

void SkeletonView::paintOverlay(QPainter& painter) const {
  painter.setRenderHint(QPainter::Antialiasing);
  const auto pixel = [&](const Eigen::Vector3d& p) { return projectToPixels(m_camera, size(), p); };
  // Pins: a dark ring around each pinned joint.
  painter.setBrush(Qt::NoBrush);
  painter.setPen(QPen(QColor(40, 40, 40), 2.0));
  for (const int j : m_pinned) {
    if (std::size_t(j) >= m_world.positions.size()) continue;
    const QPointF at = pixel(m_world.positions[std::size_t(j)]);
    if (std::isfinite(at.x())) painter.drawEllipse(at, 8.0, 8.0);
  }
  // The drag: a cross at the target, a dashed line from the joint to it.
  if (m_dragTarget && m_dragJoint >= 0 && std::size_t(m_dragJoint) < m_world.positions.size()) {
    const QPointF joint = pixel(m_world.positions[std::size_t(m_dragJoint)]);
    const QPointF target = pixel(*m_dragTarget);
    if (std::isfinite(joint.x()) && std::isfinite(target.x())) {
      painter.setPen(QPen(QColor(200, 40, 40), 1.5, Qt::DashLine));
      painter.drawLine(joint, target);
      painter.setPen(QPen(QColor(200, 40, 40), 2.0));
      painter.drawLine(target + QPointF(-6, -6), target + QPointF(6, 6));
      painter.drawLine(target + QPointF(-6, 6), target + QPointF(6, -6));
    }
  }
  QPointF at;
  const QString label = hoverLabel(&at);
  drawLabel(painter, at, label);
}

void SkeletonView::setJointDragEnabled(bool on) {
  m_jointDrag = on;
  if (!on) {
    m_dragJoint = -1;
    m_dragTarget.reset();
  }
  refresh();
}

Eigen::Vector3d SkeletonView::dragTarget(const Eigen::Vector3d& from, QPointF pixel) const {
  // The plane through `from` facing the camera: move along the camera's right and up by the
  // pixel offset, scaled by the world size of a pixel at from's depth.
  const QPointF at = projectToPixels(m_camera, size(), from);
  const Eigen::Vector3d right = m_camera.right(), up = m_camera.up();
  const Eigen::Vector3d forward = up.cross(right);
  const double depth = std::abs((from - m_camera.eye()).dot(forward));
  const double perPixel =
      2.0 * depth * std::tan(0.5 * m_camera.fovDegrees * M_PI / 180.0) / std::max(1, height());
  if (!std::isfinite(at.x()) || !(perPixel > 0.0)) return from;
  return from + right * (pixel.x() - at.x()) * perPixel - up * (pixel.y() - at.y()) * perPixel;
}

void SkeletonView::cancelJointDrag() {
  m_dragJoint = -1;
  m_dragTarget.reset();
  refresh();
}

void SkeletonView::setPinnedJoints(std::vector<int> joints) {
  std::sort(joints.begin(), joints.end());
  joints.erase(std::unique(joints.begin(), joints.end()), joints.end());
  if (joints == m_pinned) return;
  m_pinned = std::move(joints);
  emit pinnedJointsChanged();
  refresh();
}

void SkeletonView::setDragTarget(std::optional<Eigen::Vector3d> target) {
  m_dragTarget = target;
  refresh();
}

void SkeletonView::resizeEvent(QResizeEvent*) {
  // An automatic framing fits the new size (the window is laid out after the clip is opened).
  if (m_autoFramed && m_frameRadius > 0.0)
    m_camera.distance = m_camera.fitDistance(m_frameRadius, size());
  refresh();
}

bool SkeletonView::event(QEvent* event) {
  // Home here resets the camera; the window's Home action (first frame) must not take it.
  // The tooltip names the joint under the mouse; elsewhere it is the view's help.
  if (event->type() == QEvent::ToolTip && m_hovered >= 0) {
    QToolTip::showText(static_cast<QHelpEvent*>(event)->globalPos(),
                       QString::fromStdString(m_skeleton.joints[std::size_t(m_hovered)].name),
                       this);
    return true;
  }
  if (event->type() == QEvent::ShortcutOverride) {
    auto* key = static_cast<QKeyEvent*>(event);
    if (key->key() == Qt::Key_Home && key->modifiers() == Qt::NoModifier) {
      event->accept();
      return true;
    }
  }
  return QWidget::event(event);
}

void SkeletonView::keyPressEvent(QKeyEvent* event) {
  if (event->key() == Qt::Key_Home && event->modifiers() == Qt::NoModifier) {
    resetCamera();
    return;
  }
  QWidget::keyPressEvent(event);
}

void SkeletonView::mousePressEvent(QMouseEvent* event) {
  m_lastMouse = event->position().toPoint();
  m_pressMouse = m_lastMouse;
  m_dragMoved = false;
  m_dragJoint = -1;
  if (m_jointDrag && event->button() == Qt::LeftButton &&
      !(event->modifiers() & Qt::ShiftModifier)) {
    const int joint = jointAt(event->position());
    if (joint >= 0) {
      m_dragJoint = joint;
      m_dragFrom = m_world.positions[std::size_t(joint)];
    }
  }
}

void SkeletonView::mouseReleaseEvent(QMouseEvent* event) {
  const QPoint p = event->position().toPoint();
  if (m_dragJoint >= 0 && m_dragMoved) {
    const int joint = m_dragJoint;
    m_dragJoint = -1;
    m_dragTarget.reset();
    emit jointDragFinished(joint);
    refresh();
    return;
  }
  m_dragJoint = -1;
  // A click (no drag) on a joint selects it; with Shift (joint dragging on) pins or unpins it.
  if (event->button() == Qt::LeftButton && (p - m_pressMouse).manhattanLength() <= 3) {
    const int joint = jointAt(event->position());
    if (joint < 0) return;
    if (m_jointDrag && (event->modifiers() & Qt::ShiftModifier)) {
      std::vector<int> pins = m_pinned;
      const auto it = std::find(pins.begin(), pins.end(), joint);
      if (it == pins.end()) {
        pins.push_back(joint);
      } else {
        pins.erase(it);
      }
      setPinnedJoints(std::move(pins));
    } else {
      setSelectedJoint(joint);
    }
  }
}

void SkeletonView::mouseMoveEvent(QMouseEvent* event) {
  const QPoint p = event->position().toPoint();
  const QPoint d = p - m_lastMouse;
  m_lastMouse = p;
  if ((event->buttons() & Qt::LeftButton) && m_dragJoint >= 0) {
    if (!m_dragMoved && (p - m_pressMouse).manhattanLength() <= 3) return;
    if (!m_dragMoved) {
      m_dragMoved = true;
      emit jointDragStarted(m_dragJoint, m_dragFrom);
      if (m_dragJoint < 0) return;  // the controller refused the drag
    }
    const Eigen::Vector3d target = dragTarget(m_dragFrom, event->position());
    m_dragTarget = target;
    emit jointDragged(m_dragJoint, target);
    refresh();
    return;
  }
  if (event->buttons() & Qt::LeftButton) {
    m_camera.orbit(d.x(), d.y());
  } else if (event->buttons() & (Qt::MiddleButton | Qt::RightButton)) {
    m_camera.panBy(d.x(), d.y(), size());
  } else {
    const int joint = jointAt(event->position());
    if (joint != m_hovered) {
      m_hovered = joint;
      const QString name = joint >= 0
                               ? QString::fromStdString(m_skeleton.joints[std::size_t(joint)].name)
                               : QString();
      if (name.isEmpty()) {
        QToolTip::hideText();
      } else {
        QToolTip::showText(event->globalPosition().toPoint(), name, this);
      }
      refresh();
    }
    return;
  }
  m_autoFramed = false;
  refresh();
}

void SkeletonView::leaveEvent(QEvent*) {
  if (m_hovered < 0) return;
  m_hovered = -1;
  refresh();
}

void SkeletonView::wheelEvent(QWheelEvent* event) {
  m_camera.zoom(event->angleDelta().y() / 120.0);
  m_autoFramed = false;
  refresh();
}

}  // namespace motionmap::studio
