#pragma once
// MPI and PETSc for a partitioned run (solver = petsc), owned by the program, and how a launch of several
// ranks ends when one of them fails (docs/cluster.md "When a rank fails"). Included once, by main.cpp, in a
// build with PETSc.
//
// The ranks read, check and decide alike, so most failures are every rank's at once, and a check that can
// fail on one part alone is agreed before anyone throws (on_every_part, core/subdomain.hpp). What is left is
// a failure of one rank alone: a file rank 0 cannot write, memory, a deck one rank cannot read. The others
// would wait in their next collective call for ever. So a rank that fails sends its exit code and its
// one-line message to every other rank, and a thread of each rank listens for them: a rank that has neither
// failed nor finished kGrace after such a notice is waiting for the failed one, and ends the launch
// (MPI_Abort with the failed rank's exit code), rank 0 printing the lowest failed rank's message first and
// recording it in the run's folder; the other ranks give rank 0 the time to. Where MPI cannot give a
// listening thread (MPI_THREAD_MULTIPLE), or GAPFE_RANK_LISTENER=0 turns it off (Open MPI's older
// InfiniBand transport does not run under MPI_THREAD_MULTIPLE), a failed rank waits for the others at most
// kBackstop and then aborts the launch. The command starts MPI before a run reads its deck
// (app/launch.hpp, start_launch), so that a rank that cannot read it is heard.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <mutex>
#include <optional>
#include <petscsys.h>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace program {

class Launch {
 public:
  /// How long a notice may stand before a rank that has not failed ends the launch. Ranks that fail alike
  /// (the usual case) fail within the same collective call; this covers the time a rank needs to get from
  /// there to its own notice.
  static constexpr auto kGrace = std::chrono::milliseconds(500);
  /// A rank other than 0 waits longer when the failure is not rank 0's, so that rank 0, which speaks and
  /// writes, ends the launch when it is waiting too.
  static constexpr auto kGraceNotZero = std::chrono::milliseconds(2000);
  static constexpr auto kBackstop     = std::chrono::minutes(2);

  // -skip_petscrc: PETSc's options come from the command line and PETSC_OPTIONS only, never from a
  // petscrc in the working or home folder (running in someone else's case folder would adopt its
  // options: a solver, or -log_view :FILE writing over FILE); -options_file FILE still names one.
  /// `launch_size`: the processes of this launch (app::launcher_ranks); `listen`: whether a launch of
  /// several may have its listening thread.
  Launch(const char* program, int launch_size, bool listen)
      : words_{program, "-skip_petscrc"}, listen_(listen && launch_size > 1) {}
  Launch(const Launch&)            = delete;
  Launch& operator=(const Launch&) = delete;

  /// Starts MPI (with a listening thread where it can) and PETSc, once; this rank and the number of ranks.
  /// A second call is the partitioned run's (app/launch.hpp, partition()): from there on the ranks meet in
  /// collective calls, so a rank that goes on running after another failed is one that waits.
  std::pair<int, int> start(const std::vector<std::string>& options) {
    if (started_) {
      collective_ = true;
      return {rank_, size_};
    }
    if (mpi_up_)
      throw std::runtime_error("PETSc did not start");  // a second try after PetscInitialize failed
    int argc     = 0;
    char** argv  = nullptr;
    int provided = MPI_THREAD_SINGLE;
    if (MPI_Init_thread(&argc, &argv, listen_ ? MPI_THREAD_MULTIPLE : MPI_THREAD_SINGLE, &provided) !=
        MPI_SUCCESS)
      throw std::runtime_error("MPI_Init_thread failed");
    mpi_up_ = true;
    words_.insert(words_.end(), options.begin(), options.end());
    for (auto& w : words_) pointers_.push_back(w.data());
    pointers_.push_back(nullptr);
    argc = static_cast<int>(words_.size());
    argv = pointers_.data();
    if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0)
      throw std::runtime_error("PetscInitialize failed");
    started_ = true;
    MPI_Comm_dup(MPI_COMM_WORLD, &codes_);    // the exit codes' own channel (finish())
    MPI_Comm_dup(MPI_COMM_WORLD, &notices_);  // and the failures'
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    if (listen_ && provided >= MPI_THREAD_MULTIPLE && size_ > 1)
      listener_ = std::thread([this] { listen(); });
    return {rank_, size_};
  }

  /// Whether MPI has started (a process may no longer re-execute itself).
  bool mpi_up() const { return mpi_up_; }

  /// This rank's run has failed and is closing its files: it is no longer one that waits for the others.
  void failing() { state_ = kFailed; }

  /// What to record in the run's folder should this rank end the launch (Process::on_ended); empty: nothing.
  void on_ended(std::function<void(const std::string&)> record) {
    const std::lock_guard<std::mutex> lock(mutex_);
    ended_ = std::move(record);
  }

  /// This rank has failed with exit code `code` and message `line` (what rank 0 prints for it).
  void failed(int code, const std::string& line) {
    state_   = kFailed;
    failure_ = Notice{code, line};
    if (started_) notify();
  }

  /// The worst exit code of all ranks, then PETSc and MPI end. Rank 0 says why when another rank failed
  /// and it did not (the failed rank's line, which only rank 0 prints).
  int finish(int code) {
    state_ = code != 0 ? kFailed : kDone;
    if (!started_) {
      if (mpi_up_) MPI_Abort(MPI_COMM_WORLD, code != 0 ? code : 1);  // PETSc did not start: nothing agrees
      return code;
    }
    if (code != 0 && !failure_) failed(code, std::string());
    int worst           = code;
    MPI_Request request = MPI_REQUEST_NULL;
    MPI_Iallreduce(&code, &worst, 1, MPI_INT, MPI_MAX, codes_, &request);
    const auto deadline = std::chrono::steady_clock::now() + kBackstop;
    for (int done = 0;;) {
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      if (done) break;
      if (code != 0 && std::chrono::steady_clock::now() > deadline) {
        std::fprintf(
            stderr, "gapfe: rank %d failed and the other ranks did not finish: aborting the launch\n", rank_);
        MPI_Abort(MPI_COMM_WORLD, code);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    end_listening();
    if (rank_ == 0 && worst != 0 && !failure_ && heard_from_ >= 0)
      std::fprintf(stderr, "gapfe: %s\n", heard_line().c_str());
    MPI_Comm_free(&codes_);
    MPI_Comm_free(&notices_);
    PetscFinalize();
    MPI_Finalize();
    return worst;
  }

 private:
  enum State : int { kRunning, kFailed, kDone };
  struct Notice {
    int code = 0;
    std::string line;
  };
  static constexpr int kTag         = 1;
  static constexpr int kNoticeBytes = 1024;  // an exit code and a line, cut to fit

  /// Sends this rank's failure to every other rank, once.
  void notify() {
    if (notified_ || size_ < 2) return;
    notified_ = true;
    buffer_.assign(sizeof(int), 0);
    std::memcpy(buffer_.data(), &failure_->code, sizeof(int));
    buffer_.insert(buffer_.end(), failure_->line.begin(),
                   failure_->line.begin() + static_cast<std::ptrdiff_t>(std::min<std::size_t>(
                                                failure_->line.size(), kNoticeBytes - sizeof(int))));
    sends_.assign(static_cast<std::size_t>(size_), MPI_REQUEST_NULL);
    for (int to = 0; to < size_; ++to)
      if (to != rank_)
        MPI_Isend(buffer_.data(), static_cast<int>(buffer_.size()), MPI_CHAR, to, kTag, notices_,
                  &sends_[static_cast<std::size_t>(to)]);
  }

  /// The listening thread: keeps the lowest failed rank's notice, and ends the launch when this rank has
  /// neither failed nor finished kGrace after the first.
  void listen() {
    std::vector<char> in(kNoticeBytes);
    MPI_Request request = MPI_REQUEST_NULL;
    MPI_Irecv(in.data(), kNoticeBytes, MPI_CHAR, MPI_ANY_SOURCE, kTag, notices_, &request);
    std::optional<std::chrono::steady_clock::time_point> since;
    while (!stop_) {
      int done = 0;
      MPI_Status status;
      MPI_Test(&request, &done, &status);
      if (done) {
        keep(in, status);
        if (!since) since = std::chrono::steady_clock::now();
        MPI_Irecv(in.data(), kNoticeBytes, MPI_CHAR, MPI_ANY_SOURCE, kTag, notices_, &request);
        continue;
      }
      const auto grace = rank_ == 0 || heard_from_ == 0 ? kGrace : kGraceNotZero;
      if (since && state_ == kRunning && collective_ && std::chrono::steady_clock::now() - *since > grace)
        end_launch();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    MPI_Cancel(&request);
    MPI_Status status;
    MPI_Wait(&request, &status);
    int cancelled = 0;
    MPI_Test_cancelled(&status, &cancelled);
    if (!cancelled) keep(in, status);
  }

  void keep(const std::vector<char>& in, const MPI_Status& status) {
    ++received_;
    if (heard_from_ >= 0 && heard_from_ < status.MPI_SOURCE) return;
    int bytes = 0;
    MPI_Get_count(&status, MPI_CHAR, &bytes);
    heard_from_ = status.MPI_SOURCE;
    heard_      = Notice{};
    std::memcpy(&heard_.code, in.data(), sizeof(int));
    heard_.line.assign(in.data() + sizeof(int), in.data() + std::max<int>(bytes, sizeof(int)));
  }

  /// Rank 0 says why (the lowest failed rank's line, naming that rank) and records it in the run's
  /// folder, then every rank ends. Rank 0 did not end the launch in time when another rank gets here and
  /// the failure is not rank 0's (rank 0 busy, writing): the lowest rank that did not fail says it then.
  [[noreturn]] void end_launch() {
    const std::string line = heard_line();
    if (rank_ == 0 || (heard_from_ != 0 && rank_ == (heard_from_ == 1 ? 2 : 1))) {
      std::fprintf(stderr, "gapfe: %s\n", line.c_str());
      std::fflush(stderr);
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (ended_) ended_(line);
    }
    MPI_Abort(MPI_COMM_WORLD, heard_.code != 0 ? heard_.code : 1);
    std::abort();  // not reached: MPI_Abort does not return
  }

  /// The lowest failed rank's line, naming the rank: "rank 1: cannot open the deck ...".
  std::string heard_line() const {
    std::string line       = heard_.line;
    const std::string head = "gapfe: ";
    if (line.rfind(head, 0) == 0) line.erase(0, head.size());
    if (line.empty()) line = "failed (exit status " + std::to_string(heard_.code) + ")";
    return "rank " + std::to_string(heard_from_) + ": " + line;
  }

  /// Every rank is in finish(): stops the listener and receives the notices still on their way, so that no
  /// message is left unmatched when MPI ends.
  void end_listening() {
    if (listener_.joinable()) {
      stop_ = true;
      listener_.join();
    }
    std::vector<int> sent(static_cast<std::size_t>(size_), 0), coming(sent.size(), 0);
    if (notified_)
      for (int to = 0; to < size_; ++to) sent[static_cast<std::size_t>(to)] = to != rank_;
    MPI_Allreduce(sent.data(), coming.data(), size_, MPI_INT, MPI_SUM, notices_);
    std::vector<char> in(kNoticeBytes);
    while (received_ < coming[static_cast<std::size_t>(rank_)]) {
      MPI_Status status;
      MPI_Recv(in.data(), kNoticeBytes, MPI_CHAR, MPI_ANY_SOURCE, kTag, notices_, &status);
      keep(in, status);
    }
    MPI_Waitall(static_cast<int>(sends_.size()), sends_.data(), MPI_STATUSES_IGNORE);
  }

  std::vector<std::string> words_;
  std::vector<char*> pointers_;
  bool listen_ = false, mpi_up_ = false, started_ = false, notified_ = false;
  int rank_ = 0, size_ = 1;
  MPI_Comm codes_ = MPI_COMM_NULL, notices_ = MPI_COMM_NULL;
  std::atomic<int> state_{kRunning};
  std::atomic<bool> stop_{false}, collective_{false};
  std::thread listener_;
  std::optional<Notice> failure_;  // this rank's
  std::vector<char> buffer_;       // its notice, while it is sent
  std::vector<MPI_Request> sends_;
  int received_ = 0, heard_from_ = -1;  // the listener's, read after it ends
  Notice heard_;
  std::mutex mutex_;  // guards ended_, which the listener calls
  std::function<void(const std::string&)> ended_;
};

}  // namespace program
