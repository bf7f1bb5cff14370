// SPDX-License-Identifier: GPL-2.0-or-later
// MBSC_TEST_SCALE=small: the sanitizer job (scripts/sanitize.sh) sets it so that the
// heaviest numeric checks run fewer sizes and probe points under ASan (ten times slower)
// through the same code paths; the Release run of the test command leaves it unset and
// runs the full sizes. A test using it says in a comment what the small scale keeps.
#pragma once

#include <cstdlib>
#include <cstring>

namespace mbsc_test {

inline bool small_scale() {
  const char* s = std::getenv("MBSC_TEST_SCALE");
  return s != nullptr && std::strcmp(s, "small") == 0;
}

}  // namespace mbsc_test
