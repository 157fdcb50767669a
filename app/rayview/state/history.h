// Undo and redo: the states of the user's edits and settings (UndoState) before each step. A
// step is an edit made once no gesture is under way, so a drag is one step. No GL.
#pragma once

#include <vector>

#include "state/edits.h"

namespace rt::view {

class History {
public:
    /// Starts a new history at `now` (nothing to undo or redo).
    void reset(UndoState now);
    /// Once a frame: the edits and settings, when they differ from the last step's (in what the
    /// user edits, not the window's settings) and no gesture is under way (a mouse button held
    /// or a widget active), become a step.
    void track(const SceneEdits& edits, const ViewSettings& settings, bool gesture);
    /// The state before the last step into `*back`, `now` going to redo; false when there is
    /// nothing to undo. Call track(..., false) first: an edit not yet a step becomes one.
    bool undo(UndoState now, UndoState* back);
    /// The state undo() went back from into `*forward`, `now` going to undo; false when none.
    bool redo(UndoState now, UndoState* forward);
    /// The state a restore ended in: the next step starts from it.
    void settle(UndoState now) { m_committed = std::move(now); }
    size_t undo_steps() const { return m_undo.size(); }
    size_t redo_steps() const { return m_redo.size(); }

private:
    std::vector<UndoState> m_undo, m_redo;
    UndoState m_committed;  // the state the last undo step ends in
};

}  // namespace rt::view
