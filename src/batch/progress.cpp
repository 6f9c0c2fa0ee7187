// Progress of a batch: a bar redrawn in place on terminals, one line per frame in logs.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <ostream>

#include "decalcomp/batch_progress.hpp"

namespace decalcomp {

std::string formatDuration(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    const long long s = std::llround(seconds);
    if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
    return fmt::format("{}:{:02}", s / 60, s % 60);
}

double framesPerSecond(const BatchProgress& p) {
    const int processed = p.written + p.failed;
    return p.elapsed_s > 0.0 && processed > 0 ? processed / p.elapsed_s : 0.0;
}

std::optional<double> secondsLeft(const BatchProgress& p) {
    const double fps = framesPerSecond(p);
    if (fps <= 0.0) return std::nullopt;
    return (p.total - p.finished()) / fps;
}

namespace {

std::string rateText(const BatchProgress& p) {
    const auto left = secondsLeft(p);
    return fmt::format("{:.2f} fps, {} left", framesPerSecond(p), left ? formatDuration(*left) : std::string("?"));
}

std::string tallyText(const BatchProgress& p) {
    std::string s;
    if (p.skipped) s += fmt::format(", {} skipped", p.skipped);
    if (p.failed) s += fmt::format(", {} failed", p.failed);
    return s;
}

}  // namespace

ProgressPrinter::ProgressPrinter(std::ostream& out, ProgressStyle style) : out_(out), style_(style) {}

void ProgressPrinter::started(const BatchReport& report) {
    if (style_ == ProgressStyle::Quiet) return;
    const std::lock_guard lock(out_mutex_);
    const BatchPlan& plan = report.plan;
    std::string shard;
    if (plan.shard.count > 1)
        shard = fmt::format(", shard {}/{} ({}) of {} frames, from {}", plan.shard.index, plan.shard.count,
                            shardModeName(plan.shard_mode), plan.range_frames, plan.shard_source);
    const std::string where =
        report.devices.empty()
            ? fmt::format("no device (I/O only, {} workers)", report.workers_per_device)
            : fmt::format("{} ({} workers{})", fmt::join(report.devices, ", "), report.workers_per_device,
                          report.devices.size() > 1 ? " each" : "");
    out_ << fmt::format("batch: {} frames{} on {}; cameras: {}\n", plan.frames.size(), shard, where,
                        report.camera_source)
         << std::flush;
}

void ProgressPrinter::printLine(const std::string& line) {
    if (style_ == ProgressStyle::Bar) {  // above the bar: clear it; the caller or the next frame redraws it
        out_ << '\r' << std::string(last_width_, ' ') << '\r';
        last_width_ = 0;
    }
    out_ << line << '\n' << std::flush;
}

void ProgressPrinter::slowBuild(const std::string& message) {
    if (style_ == ProgressStyle::Quiet) return;
    const std::lock_guard lock(out_mutex_);
    printLine("decalcomp: note: " + message);
}

void ProgressPrinter::drawBar(const BatchProgress& p, bool force) {
    if (!force && last_draw_s_ >= 0.0 && p.elapsed_s - last_draw_s_ < 0.1) return;
    last_draw_s_ = p.elapsed_s;
    constexpr int kWidth = 30;
    const int filled = p.total > 0 ? int(double(kWidth) * p.finished() / p.total) : kWidth;
    const std::string bar = std::string(std::size_t(filled), '#') + std::string(std::size_t(kWidth - filled), '.');
    std::string line = fmt::format("[{}] {}/{} frames, {}{}", bar, p.finished(), p.total, rateText(p), tallyText(p));
    const std::size_t width = line.size();
    if (line.size() < last_width_) line += std::string(last_width_ - line.size(), ' ');
    last_width_ = width;
    out_ << '\r' << line << std::flush;
}

void ProgressPrinter::frameFinished(const FrameResult& r, const BatchProgress& p) {
    if (style_ == ProgressStyle::Quiet) return;
    const std::lock_guard lock(out_mutex_);
    std::string line;
    switch (r.status) {
        case FrameStatus::Written:
            if (style_ == ProgressStyle::Lines)
                line = fmt::format("frame {} written {} ({}/{}, {}{})", r.frame, r.output, p.finished(), p.total,
                                   rateText(p), tallyText(p));
            break;
        case FrameStatus::Skipped:
            if (style_ == ProgressStyle::Lines)
                line = fmt::format("frame {} skipped: {} exists (--resume) ({}/{})", r.frame, r.output, p.finished(),
                                   p.total);
            break;
        case FrameStatus::Failed: line = fmt::format("frame {} FAILED: {}", r.frame, r.message); break;
    }
    if (!line.empty()) printLine(line);
    if (style_ == ProgressStyle::Bar) drawBar(p, !line.empty() || p.finished() == p.total);
}

void ProgressPrinter::finished(const BatchReport& report) {
    if (style_ == ProgressStyle::Quiet) return;
    const std::lock_guard lock(out_mutex_);
    const BatchProgress& p = report.progress;
    if (style_ == ProgressStyle::Bar && last_width_ > 0) out_ << '\n';
    std::string stop;
    if (report.stopped_at)
        stop = fmt::format("; stopped at frame {}, {} not processed (--keep-going goes on past failed frames)",
                           *report.stopped_at, p.total - p.finished());
    out_ << fmt::format("batch: {} written, {} skipped, {} failed of {} frames in {} ({:.2f} fps){}\n", p.written,
                        p.skipped, p.failed, p.total, formatDuration(p.elapsed_s), framesPerSecond(p), stop)
         << "chunks: " << chunkSummary(report.chunks) << "\n"
         << std::flush;
}

}  // namespace decalcomp
