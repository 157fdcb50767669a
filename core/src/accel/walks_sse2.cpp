// The ray queries with the sse2 kernels (walks.h; isa_target.h says how).
#include "accel/walks.h"
