// SPDX-License-Identifier: MIT
// The leaf-pair prefilters at width 4; compiled with this instruction set's
// own flags (kernels/CMakeLists.txt), run only when the CPU has it.
#include "kernels/leaf_bounds_impl.h"

namespace plancheck {
namespace {
struct Sse42Tag {};  // private: these instantiations have internal linkage
using F = lanes::VFloat<4, Sse42Tag>;
using D = lanes::VDouble<2, Sse42Tag>;
}  // namespace

extern const LeafKernels kLeafKernelsSse42;
const LeafKernels kLeafKernelsSse42 = leaf_bounds_detail::make_kernels<F, D>("sse4.2");

}  // namespace plancheck
