// The panel's message line: the last error (also printed to stderr) or note, and the count of
// errors, which fails a scripted run. No GL.
#pragma once

#include <string>

namespace rt::view {

struct Messages {
    std::string text;  // the last error or note shown in the panel
    bool is_error = false;
    /// Errors so far (fail(), and a scene that did not open at start-up): a scripted run
    /// (--frames, --script, --screenshot) that had any exits 1.
    int failures = 0;
    /// Counts the messages shown (fail(), note()): an offer tied to one message (open with
    /// checker stand-ins) goes when another message replaces it.
    int serial = 0;
    /// An error: shown, printed to stderr and counted.
    void fail(std::string message);
    /// A note ("saved ...").
    void note(std::string message);
    void clear() {
        text.clear();
        is_error = false;
    }
};

}  // namespace rt::view
