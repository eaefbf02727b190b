/* semloc — an output directory that appears complete or not at all. */
#pragma once

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
 *  again by commit(). */
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
};

}  // namespace semloc
