#pragma once
// The Joints panel: a dock with the skeleton's hierarchy as a tree. Selecting a joint there
// highlights it in the 3-D view and draws its trail over the clip; a joint clicked in the view is
// selected here. It rebuilds itself whenever the view shows another skeleton.
#include <QDockWidget>

class QMainWindow;
class QMenu;
class QTreeWidget;
class QTreeWidgetItem;

namespace motionmap::studio {

class SkeletonView;

class JointPanel : public QDockWidget {
  Q_OBJECT
 public:
  JointPanel(SkeletonView* view, QWidget* parent = nullptr);
  QTreeWidget* tree() const { return m_tree; }
  /// The tree item of joint `joint` (nullptr when out of range).
  QTreeWidgetItem* item(int joint) const;

 private:
  void rebuild();
  void showSelection(int joint);

  SkeletonView* m_view;
  QTreeWidget* m_tree;
  std::vector<QTreeWidgetItem*> m_items;  ///< one per joint
};

/// Adds a hidden JointPanel for `view` on `window`'s right and its toggle (View → Joints panel)
/// to `viewMenu`. Returns the panel.
JointPanel* addJointsPanel(QMainWindow* window, SkeletonView* view, QMenu* viewMenu);

}  // namespace motionmap::studio
