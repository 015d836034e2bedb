#include "core/atomic_file.h"

#include <sys/statvfs.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <mutex>
#include <regex>
#include <set>

#include "core/error.h"
#include "core/log.h"

namespace nf {
namespace {

namespace fs = std::filesystem;

// ---- temporaries the signal handler removes ------------------------------------------------
// A fixed table of C strings: the handler may only read it and call unlink (async-signal-safe).
constexpr int kSlots = 256;
std::atomic<char*> g_slots[kSlots];
std::once_flag g_handlers_once;

extern "C" void remove_temporaries_and_reraise(int sig) {
  for (auto& slot : g_slots) {
    const char* p = slot.load();
    if (p) ::unlink(p);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void install_handlers() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (sigaction(sig, nullptr, &old) != 0) continue;
    if (old.sa_handler != SIG_DFL) continue;  // ignored (nohup) or handled by someone else: leave it
    struct sigaction sa {};
    sa.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, nullptr);
  }
}

int register_temporary(const fs::path& p) {
  std::call_once(g_handlers_once, install_handlers);
  char* copy = strdup(p.c_str());
  for (int i = 0; i < kSlots; ++i) {
    char* expected = nullptr;
    if (g_slots[i].compare_exchange_strong(expected, copy)) return i;
  }
  std::free(copy);  // table full: the destructor still removes it, only a signal would not
  return -1;
}

void unregister_temporary(int slot) {
  if (slot < 0) return;
  char* p = g_slots[slot].exchange(nullptr);
  std::free(p);
}

// .<stem>.nftmp<pid>-<n><ext> (temporaries), .<stem>.nfbak<pid>-<n><ext> (backups during commit)
// and the names of earlier versions, .<stem>.tmp<pid>-<n><ext>.
const std::regex& temp_name_pattern() {
  static const std::regex re(R"(^\..*\.(nftmp|nfbak|tmp)([0-9]+)-[0-9]+(\.[A-Za-z0-9]+)?$)");
  return re;
}

std::atomic<unsigned> g_counter{0};

fs::path hidden_name(const fs::path& target, const char* kind) {
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  // Keep the extension last so format-sniffing writers pick the right format.
  return dir / fmt::format(".{}.{}{}-{}{}", target.stem().string(), kind, getpid(), g_counter++,
                           target.extension().string());
}

bool process_alive(long pid) {
  if (pid <= 0 || pid > 0x7fffffff) return false;
  if (pid == getpid()) return true;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

bool file_system_full(const fs::path& path) {
  fs::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  struct statvfs st {};
  if (statvfs(dir.c_str(), &st) != 0) return false;
  // Less than 64 KiB free for an unprivileged writer counts as full (a write of that much failed).
  return static_cast<unsigned long long>(st.f_bavail) * st.f_frsize < 65536ULL;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  if (from.empty()) return s;
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

}  // namespace

int remove_stale_temporaries(const fs::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::smatch m;
    if (name.size() > 1024 || !std::regex_match(name, m, temp_name_pattern())) continue;
    if (!it->is_regular_file(ec)) continue;
    const long pid = std::strtol(m[2].str().c_str(), nullptr, 10);
    if (process_alive(pid)) continue;
    if (fs::remove(it->path(), ec)) {
      ++removed;
      log::debug("removed a stale temporary of an interrupted run: {}", it->path().string());
    }
  }
  return removed;
}

[[noreturn]] void fail_write(const fs::path& target, const std::string& what, const std::string& detail, int err,
                             const fs::path& temp) {
  std::string reason;
  if (err == ENOSPC || file_system_full(target)) {
    reason = "no space left on device";
  } else if (err != 0) {
    reason = std::strerror(err);
    if (!detail.empty()) reason += " (" + detail + ")";
  } else {
    reason = detail.empty() ? "unknown error" : detail;
  }
  if (!temp.empty()) {
    reason = replace_all(reason, temp.string(), target.string());
    reason = replace_all(reason, temp.filename().string(), target.filename().string());
  }
  fail(fmt::format("{}: {}: {}", target.string(), what, reason));
}

OutputTransaction::~OutputTransaction() { abandon(); }

fs::path OutputTransaction::add(const fs::path& target) {
  if (done_) fail(fmt::format("{}: output added after the transaction ended", target.string()));
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    fail(fmt::format("{}: output directory {} does not exist", target.string(), dir.string()));
  if (fs::is_directory(target, ec)) fail(fmt::format("{}: is a directory, expected a file name", target.string()));
  for (const auto& e : entries_)
    if (e.target == target) fail(fmt::format("{}: the same file is given for two outputs", target.string()));
  {
    static std::mutex mutex;
    static std::set<fs::path> cleaned;
    std::lock_guard<std::mutex> lock(mutex);
    const fs::path key = fs::weakly_canonical(dir, ec);
    if (cleaned.insert(ec ? dir : key).second) remove_stale_temporaries(dir);
  }
  Entry e{target, hidden_name(target, "nftmp"), -1};
  e.slot = register_temporary(e.temp);
  entries_.push_back(e);
  return entries_.back().temp;
}

const fs::path& OutputTransaction::temp_path(const fs::path& target) const {
  for (const auto& e : entries_)
    if (e.target == target) return e.temp;
  fail(fmt::format("{}: not an output of this command", target.string()));
}

void OutputTransaction::abandon() {
  std::error_code ec;
  for (auto& e : entries_) {
    if (!done_) fs::remove(e.temp, ec);
    unregister_temporary(e.slot);
    e.slot = -1;
  }
  done_ = true;
}

void OutputTransaction::commit() {
  if (done_) fail("output transaction committed twice");
  std::error_code ec;
  for (const auto& e : entries_)
    if (!fs::is_regular_file(e.temp, ec))
      fail(fmt::format("{}: the output was not written", e.target.string()));
  // Keep every existing target reachable under a backup name (a hard link, or a copy where the
  // file system has none) until all renames have succeeded. One output needs none: its rename is
  // atomic by itself.
  std::vector<fs::path> backups(entries_.size());
  auto drop_backups = [&] {
    for (auto& b : backups)
      if (!b.empty()) fs::remove(b, ec), b.clear();
  };
  if (entries_.size() > 1)
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      if (!fs::is_regular_file(entries_[i].target, ec)) continue;
      backups[i] = hidden_name(entries_[i].target, "nfbak");
      if (::link(entries_[i].target.c_str(), backups[i].c_str()) == 0) continue;
      fs::copy_file(entries_[i].target, backups[i], ec);
      if (ec) {
        const std::error_code failed = ec;
        backups[i].clear();
        drop_backups();
        fail_write(entries_[i].target, "cannot keep the previous file while replacing it", failed.message(),
                   failed.value());
      }
    }
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    fs::rename(entries_[i].temp, entries_[i].target, ec);
    if (!ec) continue;
    const std::error_code failed = ec;
    // Roll back: the targets already replaced get their previous files back (or disappear).
    for (std::size_t k = 0; k < i; ++k) {
      if (backups[k].empty()) {
        fs::remove(entries_[k].target, ec);
      } else {
        fs::rename(backups[k], entries_[k].target, ec);
        backups[k].clear();
      }
    }
    drop_backups();
    abandon();
    fail_write(entries_[i].target, "cannot move the finished file into place", failed.message(), failed.value());
  }
  drop_backups();
  done_ = true;
  for (auto& e : entries_) {
    unregister_temporary(e.slot);
    e.slot = -1;
  }
}

AtomicFile::AtomicFile(fs::path target) { temp_ = tx_.add(target); }

void write_text(OutputTransaction& tx, const fs::path& target, const std::string& text) {
  fs::path temp;
  try {
    temp = tx.temp_path(target);
  } catch (const Error&) {
    temp = tx.add(target);
  }
  std::ofstream out(temp, std::ios::binary);
  if (!out) fail_write(target, "cannot open for writing", "", errno);
  out << text;
  out.flush();
  const int err = out ? 0 : errno;
  out.close();
  if (!out || err) fail_write(target, "write failed", "", err ? err : errno);
}

}  // namespace nf
