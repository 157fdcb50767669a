#include "state/messages.h"

#include <cstdio>

namespace rt::view {

void Messages::fail(std::string message) {
    ++failures;
    ++serial;
    std::fprintf(stderr, "%s\n", message.c_str());
    text = std::move(message);
    is_error = true;
}

void Messages::note(std::string message) {
    ++serial;
    text = std::move(message);
    is_error = false;
}

}  // namespace rt::view
