/* semloc — CSemanticMap's visibility candidate table: switches for tests (private). */
#pragma once

#include <cstddef>

namespace semloc::detail
{
/** Whether CSemanticMap's likelihoods may use (and build) visibility candidate tables;
 *  on by default. Off: every particle scans the object grid. The outputs are the same
 *  either way (tests compare them). Process-wide; set it before concurrent calls. */
void setVisibilityTableEnabled(bool enabled);
bool visibilityTableEnabled();

/** Bytes of the last visibility table built in this process (0: none yet, or the last
 *  attempt chose the grid scan because a table would have been too large). */
size_t lastVisibilityTableBytes();
}  // namespace semloc::detail
