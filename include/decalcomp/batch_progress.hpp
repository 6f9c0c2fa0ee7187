#pragma once
// Progress of a batch on a terminal or in a log: a redrawn bar, or one line per frame.
#include <iosfwd>
#include <mutex>
#include <optional>
#include <string>

#include "decalcomp/batch.hpp"

namespace decalcomp {

enum class ProgressStyle { Bar, Lines, Quiet };

// A progress bar redrawn in place (terminals), or one line per finished frame (logs), with frames
// done, frames per second and time left; Quiet prints nothing. Writes to `out` (stderr in the CLI).
class ProgressPrinter : public BatchObserver {
public:
    ProgressPrinter(std::ostream& out, ProgressStyle style);
    void started(const BatchReport& report) override;
    void frameFinished(const FrameResult& result, const BatchProgress& progress) override;
    void finished(const BatchReport& report) override;
    void slowBuild(const std::string& message) override;  // a line above the bar

private:
    std::mutex out_mutex_;  // slowBuild comes from a device's thread
    std::ostream& out_;
    ProgressStyle style_;
    double last_draw_s_ = -1.0;
    std::size_t last_width_ = 0;
    void drawBar(const BatchProgress& progress, bool force);
    void printLine(const std::string& line);  // a line of its own, above the bar where one is drawn
};

// "12.3 fps, 0:42 left" pieces, for the printer and tests.
std::string formatDuration(double seconds);  // 0:07, 1:02:03
// Frames per second over frames actually processed (written + failed), and the time left for the rest.
double framesPerSecond(const BatchProgress& progress);
std::optional<double> secondsLeft(const BatchProgress& progress);

}  // namespace decalcomp
