/* semloc — drawFigures: the figures of a gnuplot script, one gnuplot each. */
#include "plot/Gnuplot.h"

#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/ProcessControl.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>

namespace semloc
{
std::string TFigureWarning::text() const
{
    return "figure " + figure + " was not drawn (" + script + "): " + error;
}

std::string figureWarningsMarkdown(const std::vector<TFigureWarning>& warnings)
{
    if (warnings.empty())
    {
        return {};
    }
    std::ostringstream md;
    md << "\n## Figures not drawn\n\n"
       << "gnuplot could not draw these figures; the results above do not depend on them.\n\n";
    for (const auto& w : warnings)
    {
        md << "- `" << w.figure << "` (`" << w.script << "`): `" << w.error << "`\n";
    }
    return md.str();
}

namespace detail
{
namespace
{
/** `s` in gnuplot's single quotes. */
std::string quoted(const std::string& s)
{
    std::string out = "'";
    for (const char c : s)
    {
        out += (c == '\'') ? std::string("''") : std::string(1, c);
    }
    return out + "'";
}

/** gnuplot's first error line in `log`: the first `"script" line N: ...` that is not a
 *  warning; else its last non-blank line; else `fallback`. */
std::string firstErrorLine(const std::string& log, const std::string& fallback)
{
    static const std::regex located(R"(^".*" line [0-9]+: (.*)$)");
    std::istringstream in(log);
    std::string last;
    for (std::string line; std::getline(in, line);)
    {
        std::smatch m;
        if (std::regex_match(line, m, located) && m[1].str().rfind("warning:", 0) != 0)
        {
            return line;
        }
        if (line.find_first_not_of(" \t\r^") != std::string::npos)
        {
            last = line;
        }
    }
    return last.empty() ? fallback : last;
}

std::string readAll(const std::string& path)
{
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

/** Draws one figure; its warning, if gnuplot could not. */
std::optional<TFigureWarning> drawFigure(const StagedDirectory& out, const std::string& script,
                                         const std::string& figure)
{
    const std::string log = out.path(script + ".log"), file = out.path(figure);
    int rc = 0;
    try
    {
        rc = runChildProcess({"gnuplot", "-e", "figure=" + quoted(figure), script}, log,
                             out.path(""));
    }
    catch (const Interrupted&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        std::filesystem::remove(log);
        std::filesystem::remove(file);
        return TFigureWarning{figure, script,
                              errorMessage(e) + " (is the Debian package gnuplot-nox installed?)"};
    }
    std::error_code ec;
    const bool drawn = std::filesystem::file_size(file, ec) > 0 && !ec;
    std::optional<TFigureWarning> warning;
    if (rc != 0 || !drawn)
    {
        warning = TFigureWarning{figure, script,
                                 firstErrorLine(readAll(log), "gnuplot " + waitStatusText(rc))};
        std::filesystem::remove(file);
    }
    std::filesystem::remove(log);
    return warning;
}
}  // namespace

std::string figureSelector()
{
    return "if (!exists(\"figure\")) figure = ''\n";
}

std::string figureBlock(const std::string& figure, const std::string& body)
{
    return "if (figure eq '' || figure eq " + quoted(figure) + ") {\n" + body +
           (body.empty() || body.back() == '\n' ? "" : "\n") + "}\n";
}

std::vector<TFigureWarning> drawFigures(const StagedDirectory& out, const std::string& script,
                                        const std::vector<std::string>& figures)
{
    std::vector<TFigureWarning> warnings;
    for (const auto& figure : figures)
    {
        if (auto w = drawFigure(out, script, figure))
        {
            warnings.push_back(std::move(*w));
        }
        if (interruptRequested())
        {
            throw Interrupted();
        }
    }
    return warnings;
}

std::string axisY(const std::vector<double>& values, bool logScale, const std::string& noData)
{
    const bool finite =
        std::any_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
    const bool positive = std::any_of(values.begin(), values.end(),
                                      [](double v) { return std::isfinite(v) && v > 0; });
    if (!finite)
    {
        return "set yrange [0:1]\nset label 99 " + quoted(noData) +
               " at graph 0.5, graph 0.5 center noenhanced\n";
    }
    return logScale && positive ? "set logscale y\n" : std::string();
}

std::string unsetAxisY()
{
    return "unset logscale y\nset autoscale y\nunset label 99\n";
}
}  // namespace detail
}  // namespace semloc
