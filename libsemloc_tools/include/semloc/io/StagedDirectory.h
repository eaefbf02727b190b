/* semloc — an output directory that appears complete or not at all. */
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace semloc
{
/** Files are written into a hidden staging directory beside `target`
 *  (`<parent>/.<name>.staging-XXXXXX`, holding the kOutputMarker file); commit() renames it
 *  onto `target`, replacing a previous output of semloc there. If commit() is never reached
 *  (an error), the destructor removes the staging directory: no partial output is ever left
 *  at `target`. A `target` that checkOutputDirectory() refuses (a directory semloc did not
 *  write, one holding the working directory or an input) is refused by the constructor and
 *  again by commit(). A `target` that is a symbolic link is written through: the directory it
 *  points at is replaced and the link stays (a link to nothing is refused).
 *
 *  The staging directory's marker is locked (flock) while the object lives; the constructor
 *  first removes the staging directories of `target` that no running process holds (left by a
 *  run that was killed): removeStaleStagingDirectories. */
class StagedDirectory
{
public:
    /** Checks `target` (see checkOutputDirectory, with the run's `inputs`) and creates the
     *  staging directory (and `target`'s missing parents) with the umask's permissions. */
    explicit StagedDirectory(const std::string& target,
                             const std::vector<std::string>& inputs = {});
    ~StagedDirectory();
    StagedDirectory(const StagedDirectory&) = delete;
    StagedDirectory& operator=(const StagedDirectory&) = delete;

    /** Path of `file` inside the staging directory. */
    std::string path(const std::string& file) const;
    /** Moves the staging directory to `target`. */
    void commit();
    /** The final directory. */
    const std::string& target() const { return m_target; }

private:
    std::string m_target, m_staging;
    bool m_committed = false;
    int m_lockFd = -1;
};

/** Removes the staging directories `.<name>.staging-*` beside `target` that no running
 *  process holds (their marker's lock is free, or they have no marker and are over ten minutes
 *  old); the number removed. */
size_t removeStaleStagingDirectories(const std::string& target);

}  // namespace semloc
