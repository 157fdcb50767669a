// The ray queries with the avx2 kernels (walks.h; isa_target.h says how).
#define RT_ISA_AVX2 1
#include "accel/walks.h"
