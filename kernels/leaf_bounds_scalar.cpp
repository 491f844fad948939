// SPDX-License-Identifier: MIT
// The leaf-pair prefilters at width 1 with baseline flags: the scalar
// reference every wide instantiation is tested against, and the fallback on
// CPUs without SSE4.2.
#include "kernels/leaf_bounds_impl.h"

namespace plancheck {
namespace {
struct ScalarTag {};  // private: these instantiations have internal linkage
using F = lanes::VFloat<1, ScalarTag>;
using D = lanes::VDouble<1, ScalarTag>;
}  // namespace

extern const LeafKernels kLeafKernelsScalar;
const LeafKernels kLeafKernelsScalar = leaf_bounds_detail::make_kernels<F, D>("scalar");

}  // namespace plancheck
