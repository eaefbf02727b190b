/* semloc-ini-reference: prints every ini section semloc reads, each key at its default
 * with a comment (the README's "ini reference" is this output). */
#include <semloc/ErrorMessage.h>
#include <semloc/IniReference.h>

#include <iostream>

int main()
{
    try
    {
        std::cout << semloc::iniReference();
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "semloc-ini-reference: " << semloc::errorMessage(e) << "\n";
        return 1;
    }
}
