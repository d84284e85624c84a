// bench_journal_sync: what each map_server --journal-sync mode costs per INTEGRATE (the
// table of docs/fleet.md). Appends entries of a KITTI INTEGRATE's size (1.59 MB) to a journal
// in --dir, in groups of G requests that arrive together (G robots): none (never synced),
// batch (one fdatasync per group, then the group's acks) and always (one per entry).
// ack latency: from an entry's append to the moment it may be acknowledged (none: written to
// the OS; batch: its group's sync done; always: its own sync done). No target is judged.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "service/journal.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using socc::service::Journal;
using socc::service::JournalSync;

struct Options {
  std::string dir = "/var/tmp";
  int entries = 60;
  std::size_t entry_bytes = 1590000;
  bool smoke = false;
};

struct Row {
  JournalSync sync = JournalSync::kNone;
  int group = 1;
  double seconds = 0;
  std::vector<double> ack_ms;  // one per entry
  std::int64_t syncs = 0;
};

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// Appends one group and makes it acknowledgeable; records each entry's ack latency.
void appendGroup(Journal& journal, const std::vector<std::uint8_t>& entry, int group, Row& row) {
  std::vector<Clock::time_point> started;
  for (int i = 0; i < group; ++i) {
    started.push_back(Clock::now());
    journal.append(entry.data(), entry.size());
    if (journal.syncMode() != JournalSync::kBatch) row.ack_ms.push_back(msSince(started.back()));
  }
  if (journal.syncMode() != JournalSync::kBatch) return;
  journal.sync();
  for (const auto& t : started) row.ack_ms.push_back(msSince(t));
}

Row run(const Options& o, JournalSync sync, int group) {
  const fs::path file = fs::path(o.dir) / ("bench_journal_sync." + std::to_string(::getpid()));
  const std::vector<std::uint8_t> entry(o.entry_bytes, 0x5a);
  Row row;
  row.sync = sync;
  row.group = group;
  {
    Journal journal(file, 0, sync);
    const auto start = Clock::now();
    for (int done = 0; done < o.entries; done += group) appendGroup(journal, entry, group, row);
    row.seconds = msSince(start) / 1000.0;
    row.syncs = journal.syncs();
  }
  fs::remove(file);
  return row;
}

void printRow(const Row& r, std::size_t entry_bytes) {
  const double n = static_cast<double>(r.ack_ms.size());
  const double mean = std::accumulate(r.ack_ms.begin(), r.ack_ms.end(), 0.0) / n;
  std::printf("| %s | %d | %.0f | %.0f | %.1f | %.1f | %.1f | %lld |\n",
              socc::service::journalSyncName(r.sync), r.group, n / r.seconds,
              n * static_cast<double>(entry_bytes) / 1e6 / r.seconds, mean,
              percentile(r.ack_ms, 0.5), percentile(r.ack_ms, 0.99),
              static_cast<long long>(r.syncs));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_journal_sync: cost of map_server --journal-sync none|batch|always"};
  Options o;
  app.add_option("--dir", o.dir, "directory on the disk to measure (not tmpfs)")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  app.add_option("--entries", o.entries, "entries per row")->capture_default_str();
  app.add_option("--entry-bytes", o.entry_bytes, "bytes per entry (a KITTI INTEGRATE: 1.59 MB)")
      ->capture_default_str();
  app.add_flag("--smoke", o.smoke, "4 small entries per row (CI: it still runs)");
  CLI11_PARSE(app, argc, argv);
  if (o.smoke) {
    o.entries = 4;
    o.entry_bytes = 4096;
  }
  std::printf("journal in %s, %d entries of %zu bytes per row\n\n", o.dir.c_str(), o.entries,
              o.entry_bytes);
  std::printf(
      "| --journal-sync | group (robots) | entries/s | MB/s | ack ms mean | p50 | p99 | fdatasync "
      "|\n|---|---|---|---|---|---|---|---|\n");
  for (const auto sync : {JournalSync::kNone, JournalSync::kBatch, JournalSync::kAlways})
    for (const int group : {1, 4}) printRow(run(o, sync, group), o.entry_bytes);
  return 0;
}
