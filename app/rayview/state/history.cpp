#include "state/history.h"

namespace rt::view {

namespace {

// The edits and settings alike in what the user edits.
bool same_state(const SceneEdits& edits, const ViewSettings& settings, const UndoState& b) {
    ViewSettings x = settings;
    keep_window_settings(&x, b.settings);
    return x == b.settings && same_edits(edits, b.edits);
}

}  // namespace

void History::reset(UndoState now) {
    m_undo.clear();
    m_redo.clear();
    m_committed = std::move(now);
}

void History::track(const SceneEdits& edits, const ViewSettings& settings, bool gesture) {
    if (gesture || same_state(edits, settings, m_committed)) return;  // no copy per frame
    m_undo.push_back(std::move(m_committed));
    if (m_undo.size() > 500) m_undo.erase(m_undo.begin());
    m_redo.clear();
    m_committed = {edits, settings};
}

bool History::undo(UndoState now, UndoState* back) {
    if (m_undo.empty()) return false;
    m_redo.push_back(std::move(now));
    *back = std::move(m_undo.back());
    m_undo.pop_back();
    return true;
}

bool History::redo(UndoState now, UndoState* forward) {
    if (m_redo.empty()) return false;
    m_undo.push_back(std::move(now));
    *forward = std::move(m_redo.back());
    m_redo.pop_back();
    return true;
}

}  // namespace rt::view
