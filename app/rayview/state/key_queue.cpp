#include "state/key_queue.h"

namespace rt::view {

KeyQueue& key_queue() {
    static KeyQueue queue;
    return queue;
}

}  // namespace rt::view
