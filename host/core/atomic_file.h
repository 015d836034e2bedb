#pragma once
// Output files that appear completely or not at all (docs/robustness.md).
//
// OutputTransaction: every output of one command is first written to a hidden temporary in its
// target's directory (.<stem>.nftmp<pid>-<n><ext>); commit() renames them all into place. If a
// rename fails, the targets already replaced get their previous contents back (kept as hard
// links until the end of commit) and the temporaries are removed, so either every output is new
// or every old file is untouched. An uncommitted transaction removes its temporaries when it is
// destroyed, and on SIGINT/SIGTERM/SIGHUP (the handler unlinks them and re-raises the signal).
// Temporaries left by a killed run (SIGKILL, power loss) are removed by the next run that writes
// into the same directory, when the process that created them no longer exists.
//
// AtomicFile is a transaction of one file.
#include <filesystem>
#include <string>
#include <vector>

namespace nf {

class OutputTransaction {
 public:
  OutputTransaction() = default;
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  // Registers `target` and returns the temporary path to write it to. Fails (naming the target)
  // when its directory does not exist or the target is already part of this transaction.
  std::filesystem::path add(const std::filesystem::path& target);
  // The temporary of a registered target.
  const std::filesystem::path& temp_path(const std::filesystem::path& target) const;
  // Renames every temporary onto its target, all or nothing (see above).
  void commit();
  // Removes the temporaries now (also done by the destructor).
  void abandon();

 private:
  struct Entry {
    std::filesystem::path target, temp;
    int slot = -1;  // signal-handler registry slot
  };
  std::vector<Entry> entries_;
  bool done_ = false;
};

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  const std::filesystem::path& temp_path() const { return temp_; }
  void commit() { tx_.commit(); }

 private:
  OutputTransaction tx_;
  std::filesystem::path temp_;
};

// Writes `text` to the temporary of `target` in `tx` (adding it when needed); errors name `target`.
void write_text(OutputTransaction& tx, const std::filesystem::path& target, const std::string& text);

// Throws nf::Error "<target>: <what>: <reason>", where the reason is "no space left on device"
// when `err` is ENOSPC or the target's file system is full, else strerror(err) or `detail`.
// Occurrences of `temp` in `detail` are replaced by `target` (users never see temporary names).
[[noreturn]] void fail_write(const std::filesystem::path& target, const std::string& what, const std::string& detail,
                             int err = 0, const std::filesystem::path& temp = {});

// Removes this program's temporaries in `dir` whose creating process is gone; returns how many.
// Called once per directory by OutputTransaction::add.
int remove_stale_temporaries(const std::filesystem::path& dir);

}  // namespace nf
