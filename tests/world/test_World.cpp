/* semloc tests — World: the YAML schema of docs/design.md, accepted and rejected. */
#include <gtest/gtest.h>
#include <semloc/world/World.h>

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

using semloc::ShapeType;
using semloc::World;

namespace
{
const std::string kDesignExample = R"(name: paper_50x50
bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}      # metres, the area particles may occupy
objects:
  - {id: 1, label: wellhead, shape: box, center: [7.5, 12.5], size: [2.0, 3.0], yaw_deg: 0}
  - {id: 2, label: pillar,   shape: cylinder, center: [20.0, 5.0], radius: 0.6}
  - {id: 3, label: wreck,    shape: polygon, points: [[30, 30], [34, 31], [33, 35], [29, 34]]}
  - {id: 4, label: marker,   shape: point, center: [12.0, 40.0]}   # seen by the detector, not by sonar
beacons:                                                  # optional; acoustic transponders (LBL)
  - {id: 1, x: -5, y: -5, z: -10}
trajectory:                                               # optional; used by semloc-simulate
  speed_mps: 0.5
  waypoints: [[2, 2], [48, 2], [48, 7], [2, 7]]
)";

/** Loads `text` and returns the error message ("" when it loads). */
std::string loadError(const std::string& text)
{
    try
    {
        World::FromText(text, "bad.yaml");
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return "";
}

std::string withObject(const std::string& obj)
{
    return "bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}\nobjects:\n  - " + obj + "\n";
}
}  // namespace

TEST(World, AcceptsDesignExample)
{
    const World w = World::FromText(kDesignExample, "design.yaml");
    EXPECT_EQ(w.name, "paper_50x50");
    ASSERT_EQ(w.objects.size(), 4u);
    EXPECT_EQ(w.objects[0].shape, ShapeType::Box);
    EXPECT_EQ(w.objects[0].points.size(), 4u);
    EXPECT_NEAR(w.objects[0].extent_m, std::hypot(1.0, 1.5), 1e-12);
    EXPECT_EQ(w.objects[1].shape, ShapeType::Cylinder);
    EXPECT_DOUBLE_EQ(w.objects[1].radius, 0.6);
    EXPECT_EQ(w.objects[2].shape, ShapeType::Polygon);
    // Area centroid of the polygon lies inside its bounding box.
    EXPECT_GT(w.objects[2].center.x, 29.0);
    EXPECT_LT(w.objects[2].center.x, 34.0);
    EXPECT_EQ(w.objects[3].shape, ShapeType::Point);
    ASSERT_EQ(w.beacons.size(), 1u);
    EXPECT_EQ(w.beacons[0].z, -10.0);
    ASSERT_TRUE(w.trajectory.has_value());
    EXPECT_EQ(w.trajectory->waypoints.size(), 4u);
    EXPECT_DOUBLE_EQ(w.trajectory->speed_mps, 0.5);
}

TEST(World, RoundTripsThroughYamlText)
{
    const World a = World::FromText(kDesignExample, "design.yaml");
    const std::string path = std::string(SEMLOC_TEST_OUT) + "/world_roundtrip.yaml";
    a.saveToFile(path);
    const World b = World::FromFile(path);
    ASSERT_EQ(a.objects.size(), b.objects.size());
    for (size_t i = 0; i < a.objects.size(); i++)
    {
        EXPECT_EQ(a.objects[i].id, b.objects[i].id);
        EXPECT_EQ(a.objects[i].label, b.objects[i].label);
        EXPECT_EQ(a.objects[i].shape, b.objects[i].shape);
        EXPECT_NEAR(a.objects[i].center.x, b.objects[i].center.x, 1e-12);
        EXPECT_NEAR(a.objects[i].center.y, b.objects[i].center.y, 1e-12);
    }
    EXPECT_EQ(a.toYamlText(), b.toYamlText());
}

TEST(World, ReadsAndWritesHowSureTheMapIsOfAnObject)
{
    const World a = World::FromText(
        "bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}\nobjects:\n"
        "  - {id: 1, label: pillar, shape: cylinder, center: [5, 5], radius: 0.5, sigma_m: 0.4,"
        " p_exist: 0.8, classes: {pillar: 0.7, anchor: 0.3}}\n"
        "  - {id: 2, label: anchor, shape: point, center: [9, 9]}\n",
        "sure.yaml");
    ASSERT_EQ(a.objects.size(), 2u);
    EXPECT_EQ(a.objects[0].sigma_m, 0.4);
    EXPECT_EQ(a.objects[0].p_exist, 0.8);
    using Classes = std::vector<std::pair<std::string, double>>;
    EXPECT_EQ(a.objects[0].classes, (Classes{{"anchor", 0.3}, {"pillar", 0.7}}));  // sorted
    EXPECT_EQ(a.objects[1].sigma_m, 0.0);
    EXPECT_EQ(a.objects[1].p_exist, 1.0);
    EXPECT_TRUE(a.objects[1].classes.empty());
    // Written back only where not the defaults, and read back the same.
    const std::string text = a.toYamlText();
    EXPECT_NE(text.find("sigma_m: 0.4, p_exist: 0.8, classes: {anchor: 0.3, pillar: 0.7}"),
              std::string::npos)
        << text;
    EXPECT_EQ(text.find("p_exist", text.find("id: 2")), std::string::npos) << text;
    const World b = World::FromText(text, "again.yaml");
    EXPECT_EQ(b.objects[0].classes, a.objects[0].classes);
    EXPECT_EQ(b.toYamlText(), text);
}

TEST(World, MissingFileNamesThePath)
{
    const std::string e = []
    {
        try
        {
            World::FromFile("/nonexistent/world.yaml");
        }
        catch (const std::exception& ex)
        {
            return std::string(ex.what());
        }
        return std::string();
    }();
    EXPECT_NE(e.find("/nonexistent/world.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find("does not exist"), std::string::npos) << e;
}

// Found by tests/fuzz/fuzz_world: libfyaml loops forever on a directive line with bytes that
// are not UTF-8; the loader rejects such text first, naming the line.
TEST(World, RejectsTextThatIsNotUtf8NamingTheLine)
{
    const std::string e = []
    {
        try
        {
            World::FromText("name: w\n%" + std::string(40, '\xff') + " A\nbounds: {}\n", "w.yaml");
        }
        catch (const std::exception& ex)
        {
            return std::string(ex.what());
        }
        return std::string();
    }();
    EXPECT_NE(e.find("w.yaml': line 2: not UTF-8"), std::string::npos) << e;
    // Multi-byte UTF-8 (a label in Spanish) is accepted.
    EXPECT_NO_THROW(World::FromText(
        "name: dársena\n" + withObject("{id: 1, label: bolardo, shape: point, center: [5, 5]}"),
        "u.yaml"));
}

namespace
{
/** The error of World::FromFile(path) ("" when it loads). */
std::string fileError(const std::string& path)
{
    try
    {
        World::FromFile(path);
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return "";
}
}  // namespace

// The reader streams a file: the UTF-8 check reads it once through (in pieces: a character
// across two of them is whole), then the parser; a pipe, which cannot be read twice, is read
// whole first.
TEST(World, ReadsFilesInPiecesAndRefusesPipes)
{
    const std::string dir = std::string(SEMLOC_TEST_OUT) + "/world_pieces";
    std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());
    // A name whose 2-byte character straddles the reader's 64 KiB pieces.
    std::string name = "w";
    while (name.size() + 6 < 65535)
    {
        name += 'x';
    }
    name += "\xC3\xA1";  // á, its bytes at 65535 and 65536 of the file
    const std::string text =
        "name: " + name + "\n" + kDesignExample.substr(kDesignExample.find('\n') + 1);
    std::ofstream(dir + "/big.yaml") << text;
    ASSERT_EQ(fileError(dir + "/big.yaml"), "");
    EXPECT_EQ(World::FromFile(dir + "/big.yaml").name, name);
    // Bytes that are not UTF-8 at the end are found before a syntax error near the start.
    std::ofstream(dir + "/late.yaml") << "name: [\n" << std::string(100000, '#') << "\n# \xff\n";
    EXPECT_NE(fileError(dir + "/late.yaml").find("late.yaml': line 3: not UTF-8"),
              std::string::npos)
        << fileError(dir + "/late.yaml");
    // A pipe is refused without waiting for a writer (nothing writes this one).
    const std::string fifo = dir + "/pipe.yaml";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_NE(fileError(fifo).find("pipe.yaml' is a FIFO (a pipe), not a regular file"),
              std::string::npos)
        << fileError(fifo);
}

// Each element of `objects` is parsed as it is read; the checks across them (unique ids,
// centres in bounds written after them) follow in file order: the first error is the one a
// reading of the whole document finds.
TEST(World, ReportsTheFirstErrorInFileOrder)
{
    const std::string objects =
        "objects:\n  - {id: 1, label: a, shape: point, center: [1, 1]}\n"
        "  - {id: 1, label: b, shape: point, center: [2, 2]}\n"
        "  - {id: 3, label: c, shape: point, center: [99, 2]}\n"
        "  - {id: 4, label: d, shape: cone}\n";
    // The bounds come first in the reading, though after the objects in the file.
    EXPECT_NE(loadError(objects + "bounds: {x_min: 0, x_max: 0, y_min: 0, y_max: 9}\n")
                  .find("key 'bounds': empty area"),
              std::string::npos);
    const std::string bounds = "bounds: {x_min: 0, x_max: 9, y_min: 0, y_max: 9}\n";
    EXPECT_NE(loadError(objects + bounds).find("objects[1] (id 1): key 'id': duplicate id 1"),
              std::string::npos)
        << loadError(objects + bounds);
    const std::string unique =
        std::string(objects).replace(objects.find("id: 1, label: b"), 5, "id: 2");
    EXPECT_NE(loadError(unique + bounds)
                  .find("objects[2] (id 3): key 'center': object centre is outside bounds"),
              std::string::npos)
        << loadError(unique + bounds);
    const std::string inside = std::string(unique).replace(unique.find("[99, 2]"), 7, "[9, 2]");
    EXPECT_NE(loadError(inside + bounds).find("objects[3] (id 4): key 'shape': unknown shape"),
              std::string::npos)
        << loadError(inside + bounds);
}

struct BadCase
{
    const char* name;
    std::string text;
    std::vector<std::string> mustMention;
};

/** Each case's text is refused with an error naming `prefix` (when not empty) and every
 *  string it must mention. */
void expectRefused(const std::vector<BadCase>& cases, const std::string& prefix = "")
{
    for (const auto& c : cases)
    {
        const std::string e = loadError(c.text);
        ASSERT_FALSE(e.empty()) << c.name << ": accepted";
        if (!prefix.empty())
        {
            EXPECT_NE(e.find(prefix), std::string::npos) << c.name << ": " << e;
        }
        for (const auto& m : c.mustMention)
        {
            EXPECT_NE(e.find(m), std::string::npos) << c.name << ": '" << m << "' not in: " << e;
        }
    }
}

TEST(World, RejectsEachKindOfBadFileWithFileObjectAndKey)
{
    const std::vector<BadCase> cases = {
        {"syntax", "bounds: {x_min: 0, x_max: [\n", {"bad.yaml", "YAML syntax error"}},
        // MRPT's parser alone returned the document read so far for this one.
        {"indentation",
         "bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}\nobjects:\n"
         "  - {id: 1, label: a, shape: point, center: [5, 5]}\n   extra: 3\n",
         {"bad.yaml", "line 4, column 4: YAML syntax error"}},
        {"not a map", "- 1\n- 2\n", {"bad.yaml"}},
        {"unknown top key",
         "bounds: {x_min: 0, x_max: 1, y_min: 0, y_max: 1}\nobjects: []\nfoo: 1\n",
         {"bad.yaml", "'foo'", "unknown key"}},
        {"missing bounds", "objects: []\n", {"'bounds'", "missing"}},
        {"empty bounds",
         "bounds: {x_min: 5, x_max: 5, y_min: 0, y_max: 1}\nobjects: []\n",
         {"'bounds'", "empty"}},
        {"nan bound",
         "bounds: {x_min: 0, x_max: .nan, y_min: 0, y_max: 1}\nobjects: []\n",
         {"'x_max'", "not"}},
        {"text bound",
         "bounds: {x_min: 0, x_max: ten, y_min: 0, y_max: 1}\nobjects: []\n",
         {"'x_max'", "'ten' is not a number"}},
        {"unknown object key",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], colour: red}"),
         {"objects[0] (id 1)", "'colour'", "unknown key"}},
        {"missing id",
         withObject("{label: a, shape: point, center: [1, 1]}"),
         {"objects[0]", "'id'", "missing"}},
        {"negative id",
         withObject("{id: -3, label: a, shape: point, center: [1, 1]}"),
         {"'id'", "positive"}},
        {"fractional id",
         withObject("{id: 1.5, label: a, shape: point, center: [1, 1]}"),
         {"'id'", "integer"}},
        {"bad shape",
         withObject("{id: 1, label: a, shape: cone, center: [1, 1]}"),
         {"'shape'", "cone"}},
        {"infinite coordinate",
         withObject("{id: 1, label: a, shape: point, center: [.inf, 1]}"),
         {"'center'", "finite"}},
        {"bad point",
         withObject("{id: 1, label: a, shape: point, center: [1, 2, 3]}"),
         {"'center'", "[x, y]"}},
        {"zero radius",
         withObject("{id: 1, label: a, shape: cylinder, center: [1, 1], radius: 0}"),
         {"'radius'", "> 0"}},
        {"bad box size",
         withObject("{id: 1, label: a, shape: box, center: [1, 1], size: [1, -1]}"),
         {"'size'"}},
        {"short polygon",
         withObject("{id: 1, label: a, shape: polygon, points: [[0, 0], [1, 1]]}"),
         {"'points'", "at least 3"}},
        {"self-intersecting polygon",
         withObject("{id: 1, label: a, shape: polygon, points: [[1, 1], [5, 5], [5, 1], [1, 5]]}"),
         {"'points'", "self-intersecting"}},
        {"outside bounds",
         withObject("{id: 1, label: a, shape: point, center: [60, 1]}"),
         {"objects[0] (id 1)", "outside bounds"}},
        {"empty label",
         withObject("{id: 1, label: '', shape: point, center: [1, 1]}"),
         {"'label'"}},
        {"duplicate id",
         "bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}\nobjects:\n"
         "  - {id: 4, label: a, shape: point, center: [1, 1]}\n"
         "  - {id: 4, label: b, shape: point, center: [2, 2]}\n",
         {"objects[1] (id 4)", "duplicate id 4"}},
        {"negative sigma_m",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], sigma_m: -0.1}"),
         {"objects[0] (id 1)", "'sigma_m'", ">= 0"}},
        {"p_exist zero",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], p_exist: 0}"),
         {"'p_exist'", "(0, 1]"}},
        {"p_exist above one",
         withObject("{id: 1, label: a, shape: cylinder, center: [1, 1], radius: 1, p_exist: 1.5}"),
         {"'p_exist'", "(0, 1]"}},
        {"classes not a map",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], classes: [a, b]}"),
         {"'classes'", "expected a map"}},
        {"classes not summing to one",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], classes: {a: 0.5, b: 0.4}}"),
         {"'classes'", "sum to 0.9"}},
        {"classes without the label",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], classes: {b: 0.5, c: 0.5}}"),
         {"'classes'", "the object's label 'a'"}},
        {"class probability out of range",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], classes: {a: 1.2, b: -0.2}}"),
         {"'classes'", "(0, 1]"}},
        {"bad trajectory speed",
         "bounds: {x_min: 0, x_max: 5, y_min: 0, y_max: 5}\nobjects: []\n"
         "trajectory: {speed_mps: 0, waypoints: [[1, 1], [2, 2]]}\n",
         {"trajectory", "'speed_mps'"}},
        {"waypoint outside",
         "bounds: {x_min: 0, x_max: 5, y_min: 0, y_max: 5}\nobjects: []\n"
         "trajectory: {speed_mps: 1, waypoints: [[1, 1], [9, 2]]}\n",
         {"trajectory", "'waypoints'", "outside"}},
    };
    expectRefused(cases, "bad.yaml");
}

TEST(World, ReadsWritesAndRefusesAcousticBeacons)
{
    const char* text = R"(bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}
objects:
  - {id: 1, label: pillar, shape: cylinder, center: [5, 5], radius: 0.5}
beacons:
  - {id: 0, x: -5, y: 2.5, z: -10}
  - {id: 7, x: 55, y: 60}
)";
    const World a = World::FromText(text, "lbl.yaml");
    ASSERT_EQ(a.beacons.size(), 2u);
    EXPECT_EQ(a.beacons[0].id, 0);
    EXPECT_EQ(a.beacons[0].x, -5.0);  // outside the bounds: a beacon may be moored there
    EXPECT_EQ(a.beacons[0].y, 2.5);
    EXPECT_EQ(a.beacons[0].z, -10.0);
    EXPECT_EQ(a.beacons[1].id, 7);
    EXPECT_EQ(a.beacons[1].z, 0.0) << "z defaults to 0";
    // Written back (z only where not 0), read back the same, through a file too.
    const std::string yaml = a.toYamlText();
    EXPECT_NE(
        yaml.find("beacons:\n  - {id: 0, x: -5, y: 2.5, z: -10}\n  - {id: 7, x: 55, y: 60}\n"),
        std::string::npos)
        << yaml;
    const std::string path = std::string(SEMLOC_TEST_OUT) + "/world_beacons.yaml";
    a.saveToFile(path);
    const World b = World::FromFile(path);
    ASSERT_EQ(b.beacons.size(), 2u);
    EXPECT_EQ(b.beacons[0].z, -10.0);
    EXPECT_EQ(b.toYamlText(), yaml);
    // A world without beacons is written without the key; an empty list reads as none.
    EXPECT_EQ(
        World::FromText(withObject("{id: 1, label: a, shape: point, center: [1, 1]}"), "d.yaml")
            .toYamlText()
            .find("beacons"),
        std::string::npos);
    EXPECT_TRUE(World::FromText(
                    withObject("{id: 1, label: a, shape: point, center: [1, 1]}") + "beacons: []\n",
                    "e.yaml")
                    .beacons.empty());

    const std::string head = withObject("{id: 1, label: a, shape: point, center: [1, 1]}");
    const std::vector<BadCase> cases = {
        {"not a list", head + "beacons: {id: 1, x: 1, y: 1}\n", {"'beacons'", "list"}},
        {"not a map", head + "beacons:\n  - 3\n", {"beacons[0]", "expected a map"}},
        {"unknown key",
         head + "beacons:\n  - {id: 1, x: 1, y: 1, depth: 3}\n",
         {"beacons[0] (id 1)", "'depth'", "unknown key"}},
        {"missing y",
         head + "beacons:\n  - {id: 1, x: 1}\n",
         {"beacons[0] (id 1)", "'y'", "missing"}},
        {"missing id", head + "beacons:\n  - {x: 1, y: 1}\n", {"beacons[0]", "'id'", "missing"}},
        {"negative id",
         head + "beacons:\n  - {id: -1, x: 1, y: 1}\n",
         {"beacons[0] (id -1)", "'id'", "non-negative"}},
        {"fractional id", head + "beacons:\n  - {id: 2.5, x: 1, y: 1}\n", {"'id'", "integer"}},
        {"duplicate id",
         head + "beacons:\n  - {id: 4, x: 1, y: 1}\n  - {id: 4, x: 2, y: 2}\n",
         {"beacons[1] (id 4)", "duplicate id 4"}},
        {"non-finite x", head + "beacons:\n  - {id: 1, x: .nan, y: 1}\n", {"'x'", "not a finite"}},
        {"infinite z",
         head + "beacons:\n  - {id: 1, x: 1, y: 1, z: -.inf}\n",
         {"'z'", "not a finite"}},
        {"text y", head + "beacons:\n  - {id: 1, x: 1, y: north}\n", {"'y'", "not a number"}},
        {"far x",
         head + "beacons:\n  - {id: 1, x: 1e300, y: 1}\n",
         {"'x'", "bound of world coordinates"}},
        {"key written twice",
         head + "beacons:\n  - {id: 1, x: 1, x: 2, y: 1}\n",
         {"line 5, column", "key 'x' repeated"}},
    };
    expectRefused(cases, "bad.yaml");
}

TEST(World, ShippedLblWorldIsThePaperWorldWithBeacons)
{
    // maps/paper_50x50_lbl.yaml: the paper's bounds, objects and trajectory, plus beacons.
    World lbl = World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50_lbl.yaml");
    World paper = World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    EXPECT_EQ(lbl.beacons.size(), 3u);
    EXPECT_TRUE(paper.beacons.empty());
    lbl.beacons.clear();
    lbl.name = paper.name;
    EXPECT_EQ(lbl.toYamlText(), paper.toYamlText());
}

TEST(World, BoundsEveryCoordinateAndLength)
{
    // 1e7 m is accepted, beyond it is refused naming the key and the bound.
    const std::string big = "bounds: {x_min: -1e7, x_max: 1e7, y_min: -1e7, y_max: 1e7}\n";
    const World w = World::FromText(
        big +
            "objects:\n  - {id: 1, label: a, shape: cylinder, center: [1e7, -1e7], radius: 1e7}\n"
            "  - {id: 2, label: b, shape: point, center: [0, 0], z: -1e7, extent_m: 1e7}\n",
        "big.yaml");
    EXPECT_EQ(w.bounds.x_max, 1e7);
    EXPECT_EQ(w.objects[0].radius, 1e7);
    const std::vector<BadCase> cases = {
        {"x_max",
         "bounds: {x_min: 0, x_max: 1e300, y_min: 0, y_max: 50}\nobjects: []\n",
         {"bad.yaml': bounds: key 'x_max': '1e300' is outside [-1e+07, 1e+07] m, the bound of "
          "world coordinates"}},
        {"y_min",
         "bounds: {x_min: 0, x_max: 5, y_min: -10000001, y_max: 50}\nobjects: []\n",
         {"bad.yaml': bounds: key 'y_min': '-10000001' is outside"}},
        {"centre",
         big + "objects:\n  - {id: 1, label: a, shape: point, center: [2e7, 0]}\n",
         {"bad.yaml': objects[0] (id 1): key 'center': '2e7' is outside"}},
        {"size",
         withObject("{id: 1, label: a, shape: box, center: [1, 1], size: [1, 3e7]}"),
         {"bad.yaml': objects[0] (id 1): key 'size': '3e7' is outside"}},
        {"radius",
         withObject("{id: 1, label: a, shape: cylinder, center: [1, 1], radius: 1e8}"),
         {"bad.yaml': objects[0] (id 1): key 'radius': '1e8' is outside"}},
        {"polygon point",
         withObject("{id: 1, label: a, shape: polygon, points: [[0, 0], [1e300, 0], [0, 1]]}"),
         {"bad.yaml': objects[0] (id 1): key 'points': '1e300' is outside"}},
        {"z",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], z: -1e9}"),
         {"bad.yaml': objects[0] (id 1): key 'z': '-1e9' is outside"}},
        {"extent",
         withObject("{id: 1, label: a, shape: point, center: [1, 1], extent_m: 1e9}"),
         {"bad.yaml': objects[0] (id 1): key 'extent_m': '1e9' is outside"}},
    };
    expectRefused(cases);
}

TEST(World, RefusesATrajectoryThroughAnObjectOrOfZeroLength)
{
    const std::string objects =
        "bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}\nobjects:\n"
        "  - {id: 7, label: a, shape: box, center: [10, 10], size: [2, 2], yaw_deg: 45}\n"
        "  - {id: 8, label: b, shape: cylinder, center: [30, 10], radius: 1}\n"
        "  - {id: 9, label: c, shape: polygon, points: [[20, 30], [24, 30], [22, 34]]}\n"
        "  - {id: 10, label: d, shape: point, center: [40, 40]}\n";
    auto withPath = [&](const std::string& waypoints)
    { return objects + "trajectory: {speed_mps: 1, waypoints: " + waypoints + "}\n"; };
    // Around every object, through the point object, grazing nothing: accepted.
    EXPECT_EQ(loadError(withPath("[[2, 2], [48, 2], [48, 48], [2, 48]]")), "");
    EXPECT_EQ(loadError(withPath("[[30, 40], [48, 40]]")), "");
    EXPECT_EQ(loadError(withPath("[[29, 11.001], [31, 11.001]]")), "");  // 1 mm above the top
    const std::vector<BadCase> cases = {
        {"through the box's corner",
         withPath("[[2, 2], [2, 11.4], [20, 11.4]]"),
         {"trajectory: key 'waypoints': the leg from waypoints[1] [2, 11.4] to waypoints[2] "
          "[20, 11.4] passes through objects[0] (id 7, box)"}},
        {"across the cylinder",
         withPath("[[30, 2], [30, 20]]"),
         {"the leg from waypoints[0] [30, 2] to waypoints[1] [30, 20] passes through "
          "objects[1] (id 8, cylinder)"}},
        {"touching the cylinder's top",
         withPath("[[29, 11], [31, 11]]"),
         {"passes through objects[1] (id 8, cylinder)"}},
        {"through the polygon's tip",
         withPath("[[2, 33], [48, 33]]"),
         {"passes through objects[2] (id 9, polygon)"}},
        {"a waypoint inside",
         withPath("[[2, 2], [22, 31], [48, 2]]"),
         {"key 'waypoints': waypoints[1] [22, 31] is inside objects[2] (id 9, polygon)"}},
        {"zero length",
         withPath("[[3.5, 4], [3.5, 4], [3.5, 4]]"),
         {"trajectory: key 'waypoints': the trajectory has zero length (every waypoint is "
          "[3.5, 4])"}},
    };
    expectRefused(cases, "bad.yaml': trajectory: ");
}

#include <semloc/io/ErrorMessage.h>

TEST(ErrorMessage, KeepsMessagesDropsLocationsAndStacks)
{
    try
    {
        World::FromFile("/nonexistent/world.yaml");
        FAIL();
    }
    catch (const std::exception& e)
    {
        const std::string m = semloc::errorMessage(e);
        EXPECT_EQ(m, "world file '/nonexistent/world.yaml' does not exist");
    }
    const std::runtime_error plain("plain error");
    EXPECT_EQ(semloc::errorMessage(plain), "plain error");
}
