/* semloc — the message a user should see for an exception. */
#pragma once

#include <exception>
#include <string>

namespace semloc
{
/** The messages of an exception without MRPT's source locations and call-stack dumps
 *  (mrpt::exception_to_str shows those, which help developers, not users). Nested MRPT
 *  exceptions give one line each, outermost first. Set SEMLOC_DEBUG=1 in the environment
 *  to get mrpt::exception_to_str's full text instead. */
std::string errorMessage(const std::exception& e);

}  // namespace semloc
