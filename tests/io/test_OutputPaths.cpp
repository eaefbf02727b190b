/* semloc tests — OutputPaths: an output never replaces a user's files. */
#include <gtest/gtest.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/StagedDirectory.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
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
    static std::string fileError(
        const std::string& file, const std::vector<std::string>& in = {},
        const std::function<bool(const std::string&)>& previous = [](const std::string&)
        { return false; })
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

namespace
{
std::string readAll(const fs::path& p)
{
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/** The entries of `dir` whose names start with `prefix`. */
size_t countStartingWith(const fs::path& dir, const std::string& prefix)
{
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir))
    {
        n += e.path().filename().string().rfind(prefix, 0) == 0 ? 1 : 0;
    }
    return n;
}
}  // namespace

TEST_F(OutputPaths, OutputsAreWrittenThroughASymbolicLink)
{
    const auto ours = [](const std::string& p) { return semloc::fileStartsWith(p, "# semloc"); };
    fs::create_directory(m_dir / "elsewhere");
    write(m_dir / "elsewhere" / "out.txt", "# semloc previous\n");
    fs::create_symlink(m_dir / "elsewhere" / "out.txt", "link.txt");
    EXPECT_EQ(fileError("link.txt", {}, ours), "");
    semloc::writeOutputFiles({"link.txt"}, [](const std::vector<std::string>& tmp)
                             { std::ofstream(tmp[0]) << "# semloc new\n"; });
    EXPECT_TRUE(fs::is_symlink("link.txt")) << "the link was replaced";
    EXPECT_EQ(readAll(m_dir / "elsewhere" / "out.txt"), "# semloc new\n");
    EXPECT_EQ(countStartingWith(m_dir / "elsewhere", ".out.txt.tmp-"), 0u);

    // A link to a file of the user's is refused as the file itself; a link to nothing too.
    write(m_dir / "elsewhere" / "mine.txt", "mine\n");
    fs::create_symlink(m_dir / "elsewhere" / "mine.txt", "mine.txt");
    EXPECT_NE(fileError("mine.txt", {}, ours).find("is not a previous output"), std::string::npos);
    fs::create_symlink(m_dir / "nowhere" / "x.txt", "dangling.txt");
    EXPECT_NE(fileError("dangling.txt", {}, ours).find("is a symbolic link to"), std::string::npos);

    // A directory: the previous output the link points at is replaced, the link stays.
    {
        semloc::StagedDirectory first((m_dir / "elsewhere" / "run").string());
        std::ofstream(first.path("a.txt")) << "1";
        first.commit();
    }
    fs::create_directory_symlink(m_dir / "elsewhere" / "run", "runlink");
    {
        semloc::StagedDirectory second("runlink");
        std::ofstream(second.path("a.txt")) << "2";
        second.commit();
    }
    EXPECT_TRUE(fs::is_symlink("runlink"));
    EXPECT_EQ(readAll(m_dir / "elsewhere" / "run" / "a.txt"), "2");
    EXPECT_EQ(countStartingWith(m_dir / "work", ".runlink"), 0u);
    EXPECT_EQ(countStartingWith(m_dir / "elsewhere", ".run."), 0u);
}

TEST_F(OutputPaths, AKilledRunsLeftoversAreRemovedByTheNextRunNotALiveOnes)
{
    // A killed run's staging directory: its marker is not locked. A live one's is.
    fs::create_directory(".out.staging-dead01");
    write(fs::path(".out.staging-dead01") / semloc::kOutputMarker, "");
    write(fs::path(".out.staging-dead01") / "steps.csv", "x");
    semloc::StagedDirectory live("other");  // holds the lock on its marker
    const std::string liveStaging = fs::path(live.path("")).parent_path().filename().string();
    fs::rename(fs::path(live.path("")).parent_path(), ".out.staging-live01");
    EXPECT_EQ(semloc::removeStaleStagingDirectories("out"), 1u);
    EXPECT_FALSE(fs::exists(".out.staging-dead01"));
    EXPECT_TRUE(fs::exists(".out.staging-live01")) << "a running process's staging was removed";
    fs::rename(".out.staging-live01", liveStaging);

    // A killed run's temporary file (unlocked) goes when the same output is written again.
    write(".f.txt.tmp-dead01", "half");
    semloc::writeOutputFiles(
        {"f.txt"}, [](const std::vector<std::string>& tmp) { std::ofstream(tmp[0]) << "whole"; });
    EXPECT_FALSE(fs::exists(".f.txt.tmp-dead01"));
    EXPECT_EQ(readAll("f.txt"), "whole");
}

TEST_F(OutputPaths, AnErrorLeavesTheOutputsAsTheyWere)
{
    write("a.txt", "old a");
    try
    {
        semloc::writeOutputFiles({"a.txt", "b.txt"},
                                 [](const std::vector<std::string>& tmp)
                                 {
                                     std::ofstream(tmp[0]) << "new a";
                                     throw std::runtime_error("disk full");
                                 });
        FAIL() << "the error was swallowed";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_STREQ(e.what(), "disk full");
    }
    EXPECT_EQ(readAll("a.txt"), "old a");
    EXPECT_FALSE(fs::exists("b.txt"));
    EXPECT_EQ(countStartingWith(".", ".a.txt.tmp-") + countStartingWith(".", ".b.txt.tmp-"), 0u);
}

namespace
{
/** Runs `child` in a forked process that then waits until the parent closes `release`'s write
 *  end; returns the child's pid once it has run `child` (it writes one byte on `ready`). */
pid_t holdInChild(const std::function<void()>& child, int release[2])
{
    int ready[2];
    EXPECT_EQ(::pipe(ready), 0);
    EXPECT_EQ(::pipe(release), 0);
    const pid_t pid = ::fork();
    if (pid == 0)
    {
        ::close(ready[0]);
        ::close(release[1]);
        try
        {
            child();
        }
        catch (...)
        {
            std::_Exit(2);
        }
        const char ok = 1;
        (void)!::write(ready[1], &ok, 1);
        char c = 0;
        (void)!::read(release[0], &c, 1);  // until the parent closes its end
        std::exit(0);                      // a normal exit: the lock files go
    }
    ::close(ready[1]);
    ::close(release[0]);
    char c = 0;
    EXPECT_EQ(::read(ready[0], &c, 1), 1) << "the child could not take the lock";
    ::close(ready[0]);
    return pid;
}
}  // namespace

TEST_F(OutputPaths, ASecondWriterOfAnOutputFailsNamingTheFirstUntilItEnds)
{
    int release[2];
    const pid_t holder = holdInChild([] { semloc::checkOutputDirectory("out"); }, release);
    // Any name of the same output: relative, absolute, with a trailing separator.
    for (const std::string& name :
         {std::string("out"), (fs::current_path() / "out").string(), std::string("out/")})
    {
        try
        {
            semloc::checkOutputDirectory(name);
            ADD_FAILURE() << name << ": a second writer was let in";
        }
        catch (const std::exception& e)
        {
            EXPECT_NE(std::string(e.what()).find("is in use by process " + std::to_string(holder)),
                      std::string::npos)
                << e.what();
        }
    }
    // Another output is free; the same file output too is refused while held.
    EXPECT_NO_THROW(semloc::checkOutputDirectory("other"));
    ::close(release[1]);
    int status = 0;
    ASSERT_EQ(::waitpid(holder, &status, 0), holder);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    // The holder ended: the output is free, and this process may take it (twice: no-op).
    EXPECT_NO_THROW(semloc::checkOutputDirectory("out"));
    EXPECT_NO_THROW(semloc::lockOutput("out"));
}

TEST_F(OutputPaths, AFileOutputIsLockedAndAKilledHoldersLockIsFree)
{
    int release[2];
    const pid_t holder = holdInChild(
        [] { semloc::checkOutputFile("a.txt", {}, [](const std::string&) { return true; }); },
        release);
    EXPECT_THROW(semloc::lockOutput("a.txt"), std::exception);
    ::kill(holder, SIGKILL);  // no exit handler runs: the kernel frees the lock
    int status = 0;
    ASSERT_EQ(::waitpid(holder, &status, 0), holder);
    ::close(release[1]);
    EXPECT_NO_THROW(semloc::lockOutput("a.txt"));
}
