/* semloc — the ground-truth file: `t x y phi` per line, written and read in one place. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/io/InputFile.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/Text.h"
#include "io/TextFiles.h"

namespace semloc
{
std::string GroundTruthFile::PathFor(const std::string& rawlogPath)
{
    const std::filesystem::path p(rawlogPath);
    return (p.parent_path() / (p.stem().string() + "_gt.txt")).string();
}

void GroundTruthFile::Write(const std::vector<GroundTruthRow>& rows, const std::string& path)
{
    std::string text;
    for (const auto& r : rows)
    {
        text += detail::fixedText(r.t) + ' ' + detail::fixedText(r.x) + ' ' +
                detail::fixedText(r.y) + ' ' + detail::fixedText(r.phi) + '\n';
    }
    detail::writeFile(path, text);
}

bool GroundTruthFile::IsGroundTruthFile(const std::string& path)
{
    try
    {
        (void)Read(path);
        return true;
    }
    catch (const std::exception&)
    {
        return false;
    }
}

std::vector<GroundTruthRow> GroundTruthFile::Read(const std::string& path)
{
    (void)checkInputFile(path, "ground truth", InputKind::Text);
    std::ifstream f(path);
    if (!f)
    {
        THROW_EXCEPTION("cannot read ground truth '" + path + "'");
    }
    static const char* const kColumns[] = {"t", "x", "y", "phi"};
    std::vector<GroundTruthRow> rows;
    std::string line;
    size_t previousLine = 0;
    for (size_t n = 1; std::getline(f, line); n++)
    {
        const auto b = line.find_first_not_of(" \t\r");
        if (b == std::string::npos || line[b] == '#' || line[b] == '%')
        {
            continue;
        }
        const std::string at = mrpt::format("%s:%zu: ", path.c_str(), n);
        std::istringstream ss(line);
        std::vector<std::string> cells;
        for (std::string c; ss >> c;)
        {
            cells.push_back(c);
        }
        if (cells.size() != 4)
        {
            THROW_EXCEPTION(
                at + mrpt::format("expected 4 columns 't x y phi', found %zu", cells.size()));
        }
        double v[4];
        for (size_t k = 0; k < 4; k++)
        {
            // strtod, not >>: it reads "nan" and "inf", which get their own message.
            char* end = nullptr;
            v[k] = std::strtod(cells[k].c_str(), &end);
            if (end == cells[k].c_str() || *end != '\0')
            {
                THROW_EXCEPTION(at + "column '" + kColumns[k] + "': '" + cells[k] +
                                "' is not a number");
            }
            if (!std::isfinite(v[k]))
            {
                THROW_EXCEPTION(at + "column '" + kColumns[k] + "': '" + cells[k] +
                                "' is not finite");
            }
        }
        const GroundTruthRow r{v[0], v[1], v[2], v[3]};
        if (!rows.empty() && !(r.t > rows.back().t))
        {
            THROW_EXCEPTION(at + mrpt::format("time %.17g is not after %.17g (line %zu): times "
                                              "must increase",
                                              r.t, rows.back().t, previousLine));
        }
        rows.push_back(r);
        previousLine = n;
    }
    if (rows.empty())
    {
        THROW_EXCEPTION("ground truth '" + path + "' holds no rows 't x y phi'");
    }
    return rows;
}

}  // namespace semloc
