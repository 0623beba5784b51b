#include "scene/joint_panel.h"

#include <QAction>
#include <QHeaderView>
#include <QMainWindow>
#include <QMenu>
#include <QSignalBlocker>
#include <QTreeWidget>

#include "scene/skeleton_view.h"

namespace motionmap::studio {

namespace {
const char* sideName(JointSide side) {
  switch (side) {
    case JointSide::Left:
      return "left";
    case JointSide::Right:
      return "right";
    case JointSide::Center:
      return "centre";
  }
  return "";
}
}  // namespace

JointPanel::JointPanel(SkeletonView* view, QWidget* parent)
    : QDockWidget(tr("Joints"), parent), m_view(view), m_tree(new QTreeWidget) {
  setObjectName("jointsPanel");  // saveState/restoreState need it
  m_tree->setHeaderLabels({tr("Joint"), tr("Side")});
  // CMU's hands sit ten levels deep: a narrow indent and a column as wide as its names (a
  // scroll bar rather than cut names).
  m_tree->setIndentation(12);
  m_tree->header()->setStretchLastSection(false);
  m_tree->header()->setSectionResizeMode(0, QHeaderView::ResizeToContents);
  m_tree->header()->setSectionResizeMode(1, QHeaderView::ResizeToContents);
  m_tree->setToolTip(
      tr("The skeleton's joints as their hierarchy: select one to highlight it in the 3-D view "
         "and draw its path over the whole clip"));
  setWidget(m_tree);
  connect(m_tree, &QTreeWidget::currentItemChanged, this, [this](QTreeWidgetItem* current) {
    m_view->setSelectedJoint(current ? current->data(0, Qt::UserRole).toInt() : -1);
  });
  connect(view, &SkeletonView::skeletonChanged, this, &JointPanel::rebuild);
  connect(view, &SkeletonView::selectedJointChanged, this, &JointPanel::showSelection);
  rebuild();
}

QTreeWidgetItem* JointPanel::item(int joint) const {
  return joint >= 0 && std::size_t(joint) < m_items.size() ? m_items[std::size_t(joint)] : nullptr;
}

void JointPanel::rebuild() {
  const QSignalBlocker block(m_tree);
  m_tree->clear();
  m_items.clear();
  const Skeleton& skeleton = m_view->skeleton();
  const std::vector<JointSide>& sides = m_view->sides();
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Joint& joint = skeleton.joints[std::size_t(j)];
    // Parents come before children, so the parent's item exists.
    auto* item = joint.parent >= 0 ? new QTreeWidgetItem(m_items[std::size_t(joint.parent)])
                                   : new QTreeWidgetItem(m_tree);
    item->setText(0, QString::fromStdString(joint.name));
    const JointSide side =
        std::size_t(j) < sides.size() ? sides[std::size_t(j)] : JointSide::Center;
    item->setText(1, tr(sideName(side)));
    const Eigen::Vector3f c = side_color(side);
    item->setForeground(1, QColor::fromRgbF(c.x(), c.y(), c.z()));
    item->setData(0, Qt::UserRole, j);
    m_items.push_back(item);
  }
  for (int j = 0; j < skeleton.num_joints(); ++j) {  // children are all in now
    const Joint& joint = skeleton.joints[std::size_t(j)];
    QTreeWidgetItem* it = m_items[std::size_t(j)];
    const QString tip = tr("%1: %2 channels, %3 children, %4 end sites")
                            .arg(QString::fromStdString(joint.name))
                            .arg(joint.channels.size())
                            .arg(it->childCount())
                            .arg(joint.end_sites.size());
    it->setToolTip(0, tip);
    it->setToolTip(1, tr("Side read from the name (left blue, right red, centre ochre)"));
  }
  m_tree->expandAll();
}

void JointPanel::showSelection(int joint) {
  const QSignalBlocker block(m_tree);
  QTreeWidgetItem* it = item(joint);
  m_tree->setCurrentItem(it);
  if (it) m_tree->scrollToItem(it);
}

JointPanel* addJointsPanel(QMainWindow* window, SkeletonView* view, QMenu* viewMenu) {
  auto* panel = new JointPanel(view, window);
  window->addDockWidget(Qt::RightDockWidgetArea, panel);
  panel->hide();
  QAction* toggle = panel->toggleViewAction();
  toggle->setText(QMainWindow::tr("&Joints panel"));
  toggle->setToolTip(QMainWindow::tr("Show or hide the list of joints (the skeleton's hierarchy)"));
  viewMenu->addAction(toggle);
  return panel;
}

}  // namespace motionmap::studio
