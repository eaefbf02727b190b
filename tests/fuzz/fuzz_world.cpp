/* semloc — libFuzzer target: world YAML text -> semloc::World (docs/testing.md,
 * "Fuzzing"). Any input must either load or throw; a loaded world must round-trip through
 * toYamlText() and give finite geometry. */
#include <semloc/world/World.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    semloc::World world;
    try
    {
        world = semloc::World::FromText(text, "fuzz.yaml");
    }
    catch (const std::exception&)
    {
        return 0;  // rejected with a message: what a bad world must do
    }
    // A valid world's YAML is a valid world with the same YAML (saveToFile's promise).
    const std::string yaml = world.toYamlText();
    const semloc::World again = semloc::World::FromText(yaml, "fuzz-roundtrip.yaml");
    if (again.toYamlText() != yaml)
    {
        std::abort();
    }
    (void)world.outlineSegments();
    (void)world.isFree(0.5 * (world.bounds.x_min + world.bounds.x_max),
                       0.5 * (world.bounds.y_min + world.bounds.y_max));
    return 0;
}
