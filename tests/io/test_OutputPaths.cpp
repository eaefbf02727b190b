/* semloc tests — OutputPaths: an output never replaces a user's files. */
#include <gtest/gtest.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/StagedDirectory.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace
{
/** A fresh directory for one test, made the working directory while the test runs. */
class OutputPaths : public ::testing::Test
{
protected:
    void SetUp() override
    {
        m_previous = fs::current_path();
        m_dir = fs::path(SEMLOC_TEST_OUT) / "output_paths" /
                (::testing::UnitTest::GetInstance()->current_test_info()->name() +
                 std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir / "work");
        fs::current_path(m_dir / "work");
    }
    void TearDown() override
    {
        fs::current_path(m_previous);
        if (!HasFailure())
        {
            fs::remove_all(m_dir);
        }
    }
    static void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }
    /** The message checkOutputDirectory throws for `dir`, empty when it accepts it. */
    static std::string dirError(const std::string& dir, const std::vector<std::string>& in = {})
    {
        try
        {
            semloc::checkOutputDirectory(dir, in);
            return "";
        }
        catch (const std::exception& e)
        {
            return e.what();
        }
    }
    static std::string fileError(const std::string& file, const std::vector<std::string>& in = {},
                                 const std::function<bool(const std::string&)>& previous = nullptr)
    {
        try
        {
            semloc::checkOutputFile(file, in, previous);
            return "";
        }
        catch (const std::exception& e)
        {
            return e.what();
        }
    }

    fs::path m_dir, m_previous;
};

TEST_F(OutputPaths, DirectoryRulesKeepUsersFiles)
{
    EXPECT_EQ(dirError("new/out"), "");
    fs::create_directory("empty");
    EXPECT_EQ(dirError("empty"), "") << "an empty directory loses nothing";

    EXPECT_NE(dirError(".").find("contains the working directory"), std::string::npos);
    EXPECT_NE(dirError("..").find("contains the working directory"), std::string::npos);
    EXPECT_NE(dirError("/").find("contains the working directory"), std::string::npos);
    EXPECT_NE(dirError("sub/..").find("contains the working directory"), std::string::npos);

    fs::create_directory("mine");
    write("mine/notes.txt", "x");
    EXPECT_NE(dirError("mine").find("was not written by semloc"), std::string::npos);
    write("mine/" + std::string(semloc::kOutputMarker), "");
    EXPECT_EQ(dirError("mine"), "") << "a previous output is replaced";
    EXPECT_NE(dirError("mine", {"mine/notes.txt"}).find("contains the input 'mine/notes.txt'"),
              std::string::npos)
        << "not even a previous output when it holds an input";
    EXPECT_NE(dirError("mine", {(fs::current_path() / "mine").string()}).find("contains the input"),
              std::string::npos)
        << "an input directory";

    write("afile", "x");
    EXPECT_NE(dirError("afile").find("is not a directory"), std::string::npos);
    EXPECT_NE(dirError("").find("empty output directory name"), std::string::npos);

    // A symbolic link is followed: a link to the working directory is the working directory.
    fs::create_directory_symlink(fs::current_path(), m_dir / "link");
    EXPECT_NE(dirError((m_dir / "link").string()).find("contains the working directory"),
              std::string::npos);
}

TEST_F(OutputPaths, FileRulesKeepInputsAndForeignFiles)
{
    write("in.ini", "x");
    EXPECT_EQ(fileError("out.rawlog", {"in.ini"}), "");
    EXPECT_NE(fileError("in.ini", {"in.ini"}).find("is the input 'in.ini'"), std::string::npos);
    EXPECT_NE(fileError("./sub/../in.ini", {"in.ini"}).find("is the input"), std::string::npos);
    fs::create_hard_link("in.ini", "hard.ini");
    EXPECT_NE(fileError("hard.ini", {"in.ini"}).find("is the input"), std::string::npos)
        << "the same file by another name";
    fs::create_directory("d");
    EXPECT_NE(fileError("d").find("is a directory"), std::string::npos);
    EXPECT_NE(fileError("nodir/out.png").find("does not exist"), std::string::npos);

    write("companion.txt", "user's");
    const auto ours = [](const std::string& p) { return semloc::fileStartsWith(p, "# semloc"); };
    EXPECT_NE(fileError("companion.txt", {}, ours).find("is not a previous output"),
              std::string::npos);
    write("companion.txt", "# semloc output\n");
    EXPECT_EQ(fileError("companion.txt", {}, ours), "");
    EXPECT_EQ(fileError("absent.txt", {}, ours), "") << "a new file is always fine";
}

TEST_F(OutputPaths, StagedDirectoryMarksItsOutputAndFollowsTheUmask)
{
    const mode_t old = ::umask(027);
    {
        semloc::StagedDirectory d("out");
        std::ofstream(d.path("a.txt")) << "1";
        d.commit();
    }
    ::umask(old);
    EXPECT_TRUE(fs::exists(fs::path("out") / semloc::kOutputMarker));
    struct stat st = {};
    ASSERT_EQ(::stat("out", &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0750u) << "0777 & ~umask, not mkdtemp's 0700";

    // Replaced as a whole next time, but a directory semloc did not write is refused.
    {
        semloc::StagedDirectory d("out");
        d.commit();
    }
    EXPECT_FALSE(fs::exists("out/a.txt"));
    fs::create_directory("users");
    write("users/keep.txt", "x");
    EXPECT_THROW(semloc::StagedDirectory("users"), std::exception);
    EXPECT_TRUE(fs::exists("users/keep.txt"));

    // The target changed during the run: commit() refuses and the user's file stays.
    {
        semloc::StagedDirectory d("late");
        fs::create_directory("late");
        write("late/keep.txt", "x");
        EXPECT_THROW(d.commit(), std::exception);
    }
    EXPECT_TRUE(fs::exists("late/keep.txt"));
    for (const auto& e : fs::directory_iterator("."))
    {
        EXPECT_EQ(e.path().filename().string().find(".staging-"), std::string::npos)
            << "staging directory left: " << e.path();
    }
}

}  // namespace
