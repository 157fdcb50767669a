// Key presses between two frames, in order, as the window reports them. ImGui 1.86 samples the
// keyboard once a frame, so a tap shorter than a slow frame (pressed and released within it) was
// lost, and two taps counted once; the shortcuts read this queue instead. No GL: the window's
// key callback fills it (ui/main.cpp).
#pragma once

#include <vector>

namespace rt::view {

class KeyQueue {
public:
    /// A press (`repeat`: the key held, an auto-repeat) with the modifiers then held.
    void press(int key, bool ctrl, bool shift, bool repeat) {
        m_presses.push_back({key, ctrl, shift, repeat});
    }
    /// How many presses of `key` since the last next_frame(), auto-repeats too when `repeat`,
    /// with Ctrl held or not as `ctrl` says (Shift is the caller's: shifted()).
    int presses(int key, bool ctrl = false, bool repeat = true) const {
        int n = 0;
        for (const Press& p : m_presses)
            n += p.key == key && p.ctrl == ctrl && (repeat || !p.repeat);
        return n;
    }
    /// Whether the last press of `key` had Shift held.
    bool shifted(int key) const {
        for (auto it = m_presses.rbegin(); it != m_presses.rend(); ++it)
            if (it->key == key) return it->shift;
        return false;
    }
    /// The frame has read them.
    void next_frame() { m_presses.clear(); }

private:
    struct Press {
        int key;
        bool ctrl, shift, repeat;
    };
    std::vector<Press> m_presses;
};

/// The window's queue (one window a process).
KeyQueue& key_queue();

}  // namespace rt::view
