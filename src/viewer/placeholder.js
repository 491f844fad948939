// SPDX-License-Identifier: MIT
// Embedded instead of the viewer bundle by builds without one (PLANCHECK_VIEWER=OFF).
document.body.append("This plancheck was built without its viewer (PLANCHECK_VIEWER=OFF): the page holds the data only.");
