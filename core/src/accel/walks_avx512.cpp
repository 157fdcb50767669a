// The ray queries with the avx512 kernels (walks.h; isa_target.h says how).
#define RT_ISA_AVX512 1
#include "accel/walks.h"
