// SPDX-License-Identifier: MIT
// Keeps the support library non-empty before any shared reference exists.
namespace plancheck::testing { int support_anchor = 0; }
