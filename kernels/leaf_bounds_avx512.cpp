// SPDX-License-Identifier: MIT
// The leaf-pair prefilters at width 16; compiled with this instruction set's
// own flags (kernels/CMakeLists.txt), run only when the CPU has it.
#include "kernels/leaf_bounds_impl.h"

namespace plancheck {
namespace {
struct Avx512Tag {};  // private: these instantiations have internal linkage
using F = lanes::VFloat<16, Avx512Tag>;
using D = lanes::VDouble<8, Avx512Tag>;
}  // namespace

extern const LeafKernels kLeafKernelsAvx512;
const LeafKernels kLeafKernelsAvx512 = leaf_bounds_detail::make_kernels<F, D>("avx512");

}  // namespace plancheck
