/* semloc tools — the progress bar of the long steps, on a terminal only. */
#pragma once

#include <mrpt/core/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <iostream>
#include <memory>
#include <string>

namespace semloc::apps
{
/** Seconds as h:mm:ss. */
inline std::string clockText(double s)
{
    const long t = std::lround(s);
    return mrpt::format("%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
}

/** One line on stderr, redrawn in place, when stderr is a terminal (nothing otherwise, so a
 *  pipe or a log file gets no more than without it):
 *  `<label> [#########                     ] done/total <unit>, elapsed h:mm:ss, left h:mm:ss`
 *  (with a total of 0, not known yet: `<label>: done <unit>, elapsed h:mm:ss`). */
class ProgressBar
{
public:
    ProgressBar() : m_tty(::isatty(STDERR_FILENO) != 0) {}
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;
    /** The line is erased if it is still shown (an error's message then starts its own). */
    ~ProgressBar() { erase(); }

    /** Whether anything is drawn (stderr is a terminal). */
    bool shown() const { return m_tty; }

    /** Draws `done` of `total` `unit`s after `label`; a label other than the last one's starts
     *  a new step (the old line erased, the clock restarted). Drawn again at most 10 times a
     *  second unless the bar's fill changes or the step ends. */
    void show(const std::string& label, size_t done, size_t total, const std::string& unit)
    {
        if (!m_tty)
        {
            return;
        }
        const auto now = std::chrono::steady_clock::now();
        if (label != m_label || !m_started)
        {
            erase();
            m_label = label;
            m_t0 = now;
            m_started = true;
            m_fill = -1;
        }
        const int fill = total > 0 ? static_cast<int>(kWidth * std::min(done, total) / total) : -1;
        if (fill == m_fill && done != total && now - m_drawn < std::chrono::milliseconds(100))
        {
            return;
        }
        m_fill = fill;
        m_drawn = now;
        draw(done, total, unit, std::chrono::duration<double>(now - m_t0).count());
    }

    /** Ends the line with a newline: the bar stays (the benchmark's, when its runs are done). */
    void finish()
    {
        if (m_tty && m_length > 0)
        {
            std::cerr << "\n" << std::flush;
        }
        m_length = 0;
        m_started = false;
    }

    /** Erases the line (before other output on stderr, or at the end of a step). */
    void erase()
    {
        if (m_tty && m_length > 0)
        {
            std::cerr << "\r" << std::string(m_length, ' ') << "\r" << std::flush;
        }
        m_length = 0;
        m_started = false;
    }

private:
    static constexpr int kWidth = 30;

    void draw(size_t done, size_t total, const std::string& unit, double elapsed)
    {
        std::string line = m_label;
        if (total > 0)
        {
            const auto d = std::min(done, total);
            line +=
                (m_label.empty() ? "[" : " [") + std::string(static_cast<size_t>(m_fill), '#') +
                std::string(static_cast<size_t>(kWidth - m_fill), ' ') + "] " +
                std::to_string(done) + "/" + std::to_string(total) + " " + unit + ", elapsed " +
                clockText(elapsed) + ", left " +
                (d > 0
                     ? clockText(elapsed / static_cast<double>(d) * static_cast<double>(total - d))
                     : std::string("?"));
        }
        else
        {
            line += ": " + std::to_string(done) + " " + unit + ", elapsed " + clockText(elapsed);
        }
        line += "  ";
        // Shorter than the line it replaces: blanks over the rest.
        const size_t length = line.size();
        if (length < m_length)
        {
            line += std::string(m_length - length, ' ');
        }
        std::cerr << "\r" << line << std::flush;
        m_length = std::max(m_length, length);
    }

    bool m_tty;
    bool m_started = false;
    std::string m_label;
    std::chrono::steady_clock::time_point m_t0, m_drawn;
    int m_fill = -1;
    size_t m_length = 0;
};

/** The benchmark's bar: `done` of `total` runs, the line ended when they are all done. */
inline std::function<void(size_t, size_t)> runsProgressBar()
{
    auto bar = std::make_shared<ProgressBar>();
    return [bar](size_t done, size_t total)
    {
        bar->show("", done, total, "runs");
        if (done == total)
        {
            bar->finish();
        }
    };
}

}  // namespace semloc::apps
