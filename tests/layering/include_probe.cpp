/* Compiled as a core source is compiled (the core's include path only) by
 * check_core_sees_no_tools.cmake: with a core header it must compile, with a tools header
 * it must not. */
#include SEMLOC_PROBE_HEADER

int semlocIncludeProbe()
{
    return 0;
}
