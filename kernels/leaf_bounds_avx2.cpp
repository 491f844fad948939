// SPDX-License-Identifier: MIT
// The leaf-pair prefilters at width 8; compiled with this instruction set's
// own flags (kernels/CMakeLists.txt), run only when the CPU has it.
#include "kernels/leaf_bounds_impl.h"

namespace plancheck {
namespace {
struct Avx2Tag {};  // private: these instantiations have internal linkage
using F = lanes::VFloat<8, Avx2Tag>;
using D = lanes::VDouble<4, Avx2Tag>;
}  // namespace

extern const LeafKernels kLeafKernelsAvx2;
const LeafKernels kLeafKernelsAvx2 = leaf_bounds_detail::make_kernels<F, D>("avx2");

}  // namespace plancheck
