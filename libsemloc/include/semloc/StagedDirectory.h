/* semloc — an output directory that appears complete or not at all. */
#pragma once

#include <string>

namespace semloc
{
/** Files are written into a hidden staging directory beside `target`
 *  (`<parent>/.<name>.staging-XXXXXX`); commit() renames it onto `target`, replacing a
 *  previous `target` directory. If commit() is never reached (an error), the destructor
 *  removes the staging directory: no partial output is ever left at `target`. */
class StagedDirectory
{
public:
    /** Creates the staging directory (and `target`'s missing parents). */
    explicit StagedDirectory(const std::string& target);
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
