/* semloc-ini-reference: prints every ini section semloc reads, each key at its default
 * with a comment (docs/ini-reference.md holds this output). Takes no arguments. */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <semloc/experiment/IniReference.h>

#include <iostream>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd("Prints every ini section semloc reads, each key at its default with a comment",
                   ' ', "0.1");
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-ini-reference",
                                 [] { std::cout << semloc::iniReference(); });
}
