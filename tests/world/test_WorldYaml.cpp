/* semloc tests — reading world YAML (libyaml's events, detail::parseYaml) and writing it
 * (World::toYamlText, World::saveToFile): one parser decides what a world file says, and what
 * semloc writes it reads back. */
#include <gtest/gtest.h>
#include <semloc/observation/Labels.h>
#include <semloc/world/World.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "world/YamlSyntax.h"

using semloc::World;

namespace
{
const std::string kBounds = "name: w\nbounds: {x_min: 0, x_max: 20, y_min: 0, y_max: 20}\n";

/** Loads `text` and returns the error message ("" when it loads). */
std::string loadError(const std::string& text)
{
    try
    {
        World::FromText(text, "w.yaml");
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return "";
}

/** A world of one point object labelled `label`. */
World pointWorld(const std::string& label)
{
    World w = World::FromText(kBounds + "objects: []\n", "w.yaml");
    semloc::WorldObject o;
    o.id = 1;
    o.label = label;
    o.shape = semloc::ShapeType::Point;
    o.center = {5, 5};
    w.objects.push_back(o);
    return w;
}
}  // namespace

TEST(WorldYaml, RefusesAKeyWrittenTwiceNamingLineAndColumn)
{
    const std::string m = loadError(kBounds +
                                    "objects:\n  - {id: 1, label: a, shape: cylinder, "
                                    "center: [5, 5], radius: 1, radius: 3}\n");
    EXPECT_NE(m.find("world file 'w.yaml': line 4, column 67: key 'radius' repeated (first on "
                     "line 4)"),
              std::string::npos)
        << m;
    const std::string top = loadError(kBounds +
                                      "bounds: {x_min: 0, x_max: 9, y_min: 0, "
                                      "y_max: 9}\nobjects: []\n");
    EXPECT_NE(top.find("line 3, column 1: key 'bounds' repeated (first on line 2)"),
              std::string::npos)
        << top;
    // The same key in two maps is no repetition.
    EXPECT_EQ(loadError(kBounds + "objects:\n  - {id: 1, label: a, shape: point, center: [5, 5]}\n"
                                  "  - {id: 2, label: a, shape: point, center: [6, 5]}\n"),
              "");
}

TEST(WorldYaml, RefusesAliasesSecondDocumentsAndDeepNesting)
{
    const std::string alias =
        loadError(kBounds +
                  "objects:\n  - {id: 1, label: a, shape: point, center: &c [5, 5]}\n"
                  "  - {id: 2, label: b, shape: point, center: *c}\n");
    EXPECT_NE(alias.find("line 5, column 45: YAML alias '*c': aliases are not supported"),
              std::string::npos)
        << alias;
    const std::string second = loadError(kBounds + "objects: []\n---\nname: other\n");
    EXPECT_NE(second.find("line 4, column 1: a second YAML document"), std::string::npos) << second;
    const std::string deep = loadError("a: " + std::string(100, '[') + std::string(100, ']'));
    EXPECT_NE(deep.find("nested deeper than 64 levels"), std::string::npos) << deep;
    const std::string complexKey = loadError("? [a, b]\n: 1\n");
    EXPECT_NE(complexKey.find("a map key must be a scalar"), std::string::npos) << complexKey;
}

TEST(WorldYaml, ReadsWhatLibyamlReadsWithNothingDropped)
{
    // MRPT's reader (libfyaml) refused a plain '-' in a flow map on the console only and
    // returned the part of the file before it: the objects were dropped without an error.
    const World w = World::FromText(kBounds +
                                        "objects:\n  - {id: 1, label: -, shape: point, center: "
                                        "[5, 5]}\n  - {id: 2, label: b, shape: point, center: "
                                        "[6, 5]}\n",
                                    "w.yaml");
    ASSERT_EQ(w.objects.size(), 2u);
    EXPECT_EQ(w.objects[0].label, "-");
    // A quoted 'null' is a string; a plain one is null.
    EXPECT_EQ(World::FromText(kBounds + "objects:\n  - {id: 1, label: 'null', shape: point, "
                                        "center: [5, 5]}\n",
                              "w.yaml")
                  .objects[0]
                  .label,
              "null");
    EXPECT_NE(loadError(kBounds + "objects:\n  - {id: 1, label: null, shape: point, center: "
                                  "[5, 5]}\n")
                  .find("key 'label': expected a scalar value, got a null"),
              std::string::npos);
    // "objects:" with nothing after it is an empty world.
    EXPECT_TRUE(World::FromText(kBounds + "objects:\n", "w.yaml").objects.empty());
}

TEST(WorldYaml, ParseYamlSetsTheMarksOfEachNode)
{
    mrpt::containers::yaml::node_t doc;
    ASSERT_EQ(semloc::detail::parseYaml("a: 1\nb:\n  - x\n  - {c: 2}\n", doc), "");
    ASSERT_TRUE(doc.isMap());
    const auto& m = doc.asMap();
    ASSERT_EQ(m.size(), 2u);
    const auto& b = m.at(mrpt::containers::yaml::node_t(std::string("b")));
    ASSERT_TRUE(b.isSequence());
    EXPECT_EQ(b.asSequence()[1].marks.line, 3);
    EXPECT_EQ(b.asSequence()[1].marks.column, 4);
    EXPECT_EQ(b.asSequence()[0].as<std::string>(), "x");
}

TEST(WorldYaml, LabelsFollowOneRule)
{
    const std::string blank = loadError(kBounds +
                                        "objects:\n  - {id: 1, label: 'oil rig', "
                                        "shape: point, center: [5, 5]}\n");
    EXPECT_NE(blank.find("key 'label': label 'oil rig' holds a blank or control character"),
              std::string::npos)
        << blank;
    const std::string tooLong =
        loadError(kBounds + "objects:\n  - {id: 1, label: " + std::string(1000000, 'x') +
                  ", shape: point, center: [5, 5]}\n");
    EXPECT_NE(tooLong.find("key 'label': label of 1000000 bytes is too long (at most 65536)"),
              std::string::npos)
        << tooLong.substr(0, 300);
    EXPECT_EQ(
        loadError(kBounds + "objects:\n  - {id: 1, label: " +
                  std::string(semloc::kMaxLabelLength, 'x') + ", shape: point, center: [5, 5]}\n"),
        "");
    EXPECT_EQ(semloc::labelProblem("wellhead"), "");
    EXPECT_EQ(semloc::labelProblem("\xC3\xA9pave"), "");  // UTF-8 beyond ASCII is text
    EXPECT_NE(semloc::labelProblem("a\tb"), "");
    EXPECT_NE(semloc::labelProblem(std::string("a\x7F")), "");
    EXPECT_NE(semloc::labelProblem(""), "");
}

TEST(WorldYaml, WritesEveryLabelItReadsSoThatItReadsBack)
{
    // Labels and names YAML would read as something else unless quoted, and characters it
    // would not keep as text (line breaks, C1 controls, the byte-order mark, U+FFFF).
    const std::vector<std::string> labels = {"-",
                                             "a,b",
                                             "x}",
                                             "#c",
                                             "[q]",
                                             "%p",
                                             "a\"b",
                                             "a\\b",
                                             "~",
                                             "*x",
                                             "&y",
                                             "!t",
                                             "?",
                                             "|",
                                             "@a",
                                             "null",
                                             "Null",
                                             "NULL",
                                             "1",
                                             "a:b",
                                             "wellhead",
                                             "mooring_post",
                                             "\303\251t\303\251",
                                             "\357\273\277b",
                                             "a\342\200\250b",
                                             "a\302\200b",
                                             "\302\205x",
                                             "x\357\277\277"};
    for (const std::string& label : labels)
    {
        World w = pointWorld(label);
        w.name = "my world: #" + label;
        const std::string text = w.toYamlText();
        World back;
        ASSERT_NO_THROW(back = World::FromText(text, "w.yaml")) << text;
        EXPECT_EQ(back.objects.at(0).label, label) << text;
        EXPECT_EQ(back.name, w.name) << text;
        EXPECT_EQ(back.toYamlText(), text);
    }
    // Plain words stay as they were (the shipped worlds' text is unchanged).
    EXPECT_NE(pointWorld("mooring_post").toYamlText().find("label: mooring_post,"),
              std::string::npos);
}

TEST(WorldYaml, SaveToFileWritesNothingItCouldNotReadBack)
{
    const std::string dir = std::string(SEMLOC_TEST_OUT) + "/world_yaml";
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/bad.yaml";
    std::filesystem::remove(path);
    for (const std::string& label :
         {std::string("oil rig"), std::string(), std::string(semloc::kMaxLabelLength + 1, 'x')})
    {
        try
        {
            pointWorld(label).saveToFile(path);
            FAIL() << "wrote a label the loader refuses";
        }
        catch (const std::exception& e)
        {
            const std::string m = e.what();
            EXPECT_NE(m.find("not writing world file '" + path +
                             "': semloc could not read it back: objects[0] (id 1): key "
                             "'label': label "),
                      std::string::npos)
                << m.substr(0, 300);
        }
        EXPECT_FALSE(std::filesystem::exists(path));
    }
    const std::string good = dir + "/good.yaml";
    World w = pointWorld("buoy");
    semloc::WorldObject box;
    box.id = 2;
    box.label = "crate";
    box.shape = semloc::ShapeType::Box;
    box.center = {10, 10};
    box.size_x = 2;
    box.size_y = 1;
    for (const double yaw : {0.123456789, -2.9876543210987, 1e-9})
    {
        box.yaw = yaw;  // radians, written in degrees: read back within a rounding
        w.objects.resize(1);
        w.objects.push_back(box);
        ASSERT_NO_THROW(w.saveToFile(good)) << yaw;
        const World back = World::FromFile(good);
        EXPECT_EQ(back.objects.at(0).label, "buoy");
        EXPECT_NEAR(back.objects.at(1).yaw, yaw, 1e-15);
    }
}

TEST(WorldYaml, SaveToFileNamesTheFileAndTheReason)
{
    try
    {
        pointWorld("buoy").saveToFile("/dev/full");
        FAIL() << "a full disk went unnoticed";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("cannot write world file '/dev/full': No space left on device"),
                  std::string::npos)
            << m;
    }
}
