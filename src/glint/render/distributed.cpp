#include "glint/render/distributed.h"

#include <mpi.h>
#include <signal.h>

#include <time.h>
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "glint/error.h"
#include "glint/render/tile_stream.h"

namespace glint::mpi {

namespace {

enum Tag : int { kRequest = 101, kItems = 102, kResult = 103, kHeartbeat = 104 };
constexpr int kNoMore = -1;
using Clock = std::chrono::steady_clock;

int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

// With MPI_ERRORS_RETURN a failed call comes back here: say which rank and
// what, and fail the job rather than wait for a message that will not come.
void check(int rc, const char* call) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(rc, text, &length);
  throw JobFailure(world_rank(), std::string(call) + " failed: " + std::string(text, length));
}

// Waits for a nonblocking call to complete, sleeping between tests. Open MPI's
// blocking calls (MPI_Send, MPI_Barrier, collectives) busy-poll until done,
// taking the core from this rank's workers, or from another rank or another
// program sharing it.
void wait_calmly(MPI_Request& request, const char* call) {
  auto pause = std::chrono::microseconds(20);
  for (;;) {
    int done = 0;
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), call);
    if (done) return;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(1000));
  }
}

std::vector<char> int_bytes(const std::vector<int>& values) {
  std::vector<char> bytes(values.size() * sizeof(int));
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

// Messages sent without waiting for the receiver: a blocking MPI_Send of a
// tile's pixels spins until rank 0 takes them, which costs a worker's core
// (docs/performance.md, "Lessons that guide the code"). Every message here is bytes
// (MPI_BYTE on both sides).
class Outbox {
 public:
  Outbox() = default;
  Outbox(const Outbox&) = delete;
  Outbox& operator=(const Outbox&) = delete;
  // Left by a JobFailure with sends in flight: MPI may still read their
  // bytes until the job ends (abort_job), so they are kept, reachable.
  ~Outbox() {
    static std::mutex mutex;
    static std::deque<std::deque<Pending>> abandoned;
    if (pending_.empty()) return;
    std::lock_guard lock(mutex);
    abandoned.push_back(std::move(pending_));
  }
  void send(std::vector<char> bytes, int dest, int tag) {
    pending_.push_back(Pending{std::move(bytes), MPI_REQUEST_NULL});
    Pending& p = pending_.back();
    check(MPI_Isend(p.bytes.data(), static_cast<int>(p.bytes.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD, &p.request),
          "MPI_Isend");
    last_send_ = Clock::now();
  }
  // Frees the sends that completed.
  void poll() {
    for (Pending& p : pending_) {
      int done = 0;
      check(MPI_Test(&p.request, &done, MPI_STATUS_IGNORE), "MPI_Test");
    }
    std::erase_if(pending_, [](const Pending& p) { return p.request == MPI_REQUEST_NULL; });
  }
  // Until every send completed (the receivers took them), without spinning.
  void drain() {
    for (Pending& p : pending_) wait_calmly(p.request, "MPI_Isend");
    pending_.clear();
  }
  Clock::time_point last_send() const { return last_send_; }

 private:
  struct Pending {
    std::vector<char> bytes;  // must not move until the send completes (a deque keeps it in place)
    MPI_Request request;
  };
  std::deque<Pending> pending_;
  Clock::time_point last_send_ = Clock::now();
};

// One rank's share of the work: items from rank 0, taken by worker threads.
struct LocalWork {
  std::mutex m;
  std::condition_variable ready;  // workers wait for items
  std::condition_variable wake;   // the main thread waits for finished items
  std::deque<int> queue;
  bool closed = false;        // no more items will come
  int busy = 0;               // taken by a worker, not finished
  std::vector<int> finished;  // not yet reported by the main thread
  std::exception_ptr error;
  std::atomic<bool> stopping{false};  // the job failed: workers stop (run_items' `stop`)

  int pop() {
    std::unique_lock lock(m);
    ready.wait(lock, [&] { return !queue.empty() || closed || error; });
    if (queue.empty() || error) return kNoMore;
    const int item = queue.front();
    queue.pop_front();
    ++busy;
    return item;
  }
  void finish(int item) {
    std::lock_guard lock(m);
    --busy;
    finished.push_back(item);
    wake.notify_one();
  }
  void fail(std::exception_ptr e) {
    std::lock_guard lock(m);
    error = e;
    --busy;
    ready.notify_all();
    wake.notify_one();
  }
  // No more items, and the one in work abandoned where it can be.
  void stop() {
    std::lock_guard lock(m);
    stopping = true;
    closed = true;
    queue.clear();
    ready.notify_all();
  }
};

// Stops the rank's render thread and joins it however the run ends: a
// JobFailure leaves the function only once no thread of this rank is
// rendering (and none is left joinable, which would terminate the process).
class JoinOnExit {
 public:
  JoinOnExit(LocalWork& work, std::thread& thread) : work_(work), thread_(thread) {}
  JoinOnExit(const JoinOnExit&) = delete;
  JoinOnExit& operator=(const JoinOnExit&) = delete;
  ~JoinOnExit() {
    if (!thread_.joinable()) return;
    work_.stop();
    thread_.join();
  }

 private:
  LocalWork& work_;
  std::thread& thread_;
};

// What a finished item carries to rank 0 besides its number, and what rank 0
// does with it; no `pack`: the number alone (frames, written by the rank
// that renders them).
struct Results {
  std::function<void(int item, std::vector<char>& bytes)> pack;  // appends
  std::function<void(int item, const char* bytes, size_t size)> unpack;
};

// How the run watches for hung ranks: see render_image.
struct Watch {
  double timeout = kDefaultRankTimeout;  // seconds
  const char* noun = "tiles";
  std::function<std::string(int item)> name;  // of an item in an error message
  FaultInjection faults;                      // for tests
  std::chrono::duration<double> heartbeat() const { return std::chrono::duration<double>(std::min(1.0, timeout / 4)); }
  bool overdue(Clock::time_point since, Clock::time_point now) const {
    return std::chrono::duration<double>(now - since).count() > timeout;
  }
  std::string seconds() const {
    char text[32];
    std::snprintf(text, sizeof text, "%g", timeout);
    return text;
  }
  std::string holding(const std::vector<int>& items) const {
    std::string text = std::string("holding ") + noun;
    constexpr size_t kShown = 8;
    for (size_t i = 0; i < std::min(items.size(), kShown); ++i) {
      text += i ? ", " : " ";  // appended piece by piece: GCC 12 warns falsely on a + b here under LTO
      text += name ? name(items[i]) : std::to_string(items[i]);
    }
    if (items.size() > kShown) text += ", ... (" + std::to_string(items.size()) + " in all)";
    return text;
  }
};

std::string what_of(std::exception_ptr e) {
  try {
    std::rethrow_exception(e);
  } catch (const std::exception& x) {
    return x.what();
  } catch (...) {
    return "unknown error";
  }
}

// The faults the caller asked for (tests): this rank dies or stops, as a
// crashed or hung process would, after its first finished item.
void maybe_fail(const FaultInjection& faults, int rank, int finished) {
  if (finished <= 0) return;
  if (faults.die_rank == rank) raise(SIGKILL);
  if (faults.hang_rank == rank) raise(SIGSTOP);
}

// Waits until a local item finishes (workers wake us), or up to `pause` so
// that messages from other ranks are polled. The pause doubles while no
// message comes (1 ms to 4 ms): each poll takes the core from a worker, and
// QueueDepth keeps enough tiles queued to cover the round trips; shorter
// pauses cost CPU and rendered no faster.
constexpr auto kMinPause = std::chrono::microseconds(1000), kMaxPause = std::chrono::microseconds(4000);
void pause_until_progress(LocalWork& work, std::chrono::microseconds& pause, bool heard) {
  pause = heard ? kMinPause : std::min(pause * 2, kMaxPause);
  std::unique_lock lock(work.m);
  work.wake.wait_for(lock, pause, [&] { return !work.finished.empty() || work.error; });
}

// How many items a rank keeps queued or in work: at least `least`, more when
// items go fast, so that its workers stay busy for a few round trips to rank
// 0: a request can take milliseconds to be answered (rank 0's main thread
// shares a core with a worker) while a tile of background takes 0.1 ms, so
// a fixed queue left workers waiting (docs/performance.md).
class QueueDepth {
 public:
  QueueDepth(int least, int most) : least_(least), most_(std::max(least, most)) {}
  void finished(Clock::time_point when) {
    recent_.push_back(when);
    if (recent_.size() > kWindow) recent_.pop_front();
  }
  void answered(double seconds) { round_trip_ = round_trip_ == 0 ? seconds : 0.8 * round_trip_ + 0.2 * seconds; }
  int target() const {
    if (least_ == most_ || recent_.size() < kWindow / 4) return least_;
    const double span = std::chrono::duration<double>(recent_.back() - recent_.front()).count();
    if (span <= 0) return most_;
    const double per_second = static_cast<double>(recent_.size() - 1) / span;  // all workers together
    const double cover = std::clamp(4 * round_trip_, 0.010, 0.100);            // seconds of work queued
    return static_cast<int>(
        std::clamp(std::ceil(per_second * cover), static_cast<double>(least_), static_cast<double>(most_)));
  }
  int most() const { return most_; }

 private:
  static constexpr size_t kWindow = 32;
  int least_, most_;
  std::deque<Clock::time_point> recent_;  // when the last items finished
  double round_trip_ = 0;                 // seconds, smoothed
};

struct Traffic {
  uint64_t bytes = 0;
  std::vector<int> items_by_rank;
};

// Rank 0's main thread: hands out items 0..count-1 (to its own queue and on
// request to other ranks), takes every rank's finished items (and their
// results), until every item is done and every other rank has been told
// there is no more work. Watches the other ranks meanwhile: one that holds
// items (or that rank 0 waits for at the end) and sends nothing for
// watch.timeout seconds ends the job.
void coordinate(LocalWork& work, int count, const QueueDepth& depth, const Results& results, const Watch& watch,
                Traffic& traffic) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  traffic.items_by_rank.assign(size, 0);
  std::vector<std::vector<int>> held(size);  // handed to each rank, not reported finished
  std::vector<Clock::time_point> silent_since(size, Clock::now());
  std::vector<char> told(size, 0);  // told "no more"
  Outbox outbox;
  int next = 0, done = 0, ranks_told = 0;
  auto pause = kMinPause;
  for (;;) {
    bool heard = false;  // a message from another rank
    int flag = 0;
    MPI_Status status;
    for (check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe"); flag;
         check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe")) {
      const int from = status.MPI_SOURCE;
      int bytes = 0;
      MPI_Get_count(&status, MPI_BYTE, &bytes);
      std::vector<char> buffer(static_cast<size_t>(std::max(0, bytes)));
      check(MPI_Recv(buffer.data(), bytes, MPI_BYTE, from, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "MPI_Recv");
      heard = true;
      silent_since[from] = Clock::now();
      int number = 0;  // how many items a request wants; the item a result is of
      if (buffer.size() >= sizeof(int)) std::memcpy(&number, buffer.data(), sizeof(int));
      if (status.MPI_TAG == kRequest) {
        std::vector<int> items(std::clamp(number, 1, depth.most()), kNoMore);
        for (int& item : items)
          if (next < count) held[from].push_back(item = next++);
        if (items.back() == kNoMore && !told[from]) told[from] = 1, ++ranks_told;  // that rank asks no more
        std::vector<char> reply = int_bytes(items);
        traffic.bytes += reply.size();
        outbox.send(std::move(reply), from, kItems);
      } else if (status.MPI_TAG == kResult) {
        auto it = std::find(held[from].begin(), held[from].end(), number);
        if (it == held[from].end()) continue;  // not one of its items: cannot happen
        held[from].erase(it);
        if (results.unpack) results.unpack(number, buffer.data() + sizeof(int), buffer.size() - sizeof(int));
        ++done;
        ++traffic.items_by_rank[from];
      }  // kHeartbeat: alive, holding items
    }
    bool idle = false;
    {
      std::lock_guard lock(work.m);
      if (work.error) throw JobFailure(0, what_of(work.error));
      // Its own workers' queue is refilled whenever one finishes: no round trip.
      while (static_cast<int>(work.queue.size()) + work.busy < depth.target() && next < count)
        work.queue.push_back(next++);
      if (next >= count) work.closed = true;
      work.ready.notify_all();
      traffic.items_by_rank[0] += static_cast<int>(work.finished.size());
      done += static_cast<int>(work.finished.size());
      maybe_fail(watch.faults, 0, static_cast<int>(work.finished.size()));
      work.finished.clear();
      idle = work.closed && work.queue.empty() && work.busy == 0;
    }
    outbox.poll();
    if (done == count && idle && ranks_told == size - 1) {
      outbox.drain();  // the last "no more" answers
      return;
    }
    const auto now = Clock::now();
    for (int r = 1; r < size; ++r) {
      // Rank 0 waits for rank r: it holds items, or all is handed out and
      // rank 0 has nothing left to do but tell it so.
      const bool waiting = !held[r].empty() || (idle && !told[r]);
      if (!waiting) {
        silent_since[r] = now;
      } else if (watch.overdue(silent_since[r], now)) {
        const std::string holding =
            held[r].empty() ? "holding no " + std::string(watch.noun) + "; rank 0 waits to tell it all is done"
                            : watch.holding(held[r]);
        throw JobFailure(r, "no answer for " + watch.seconds() + " s (" + holding + "); a hung rank? (--rank-timeout)");
      }
    }
    pause_until_progress(work, pause, heard);
  }
}

// Every other rank's main thread: keeps `depth` items queued or in work,
// asking rank 0 for more, and reports each finished item (with its result).
// While it holds items it sends rank 0 a heartbeat when it has sent nothing
// for a while; and it gives up on rank 0 when an answer takes watch.timeout.
void follow(LocalWork& work, QueueDepth depth, const Results& results, const Watch& watch, Traffic& traffic) {
  const int rank = world_rank();
  Outbox outbox;
  bool exhausted = false, awaiting = false;
  int want = 0, finished_total = 0;
  auto asked = Clock::now();
  auto pause = kMinPause;
  for (;;) {
    bool heard = false;  // the reply from rank 0
    std::vector<int> finished;
    int outstanding = 0;
    bool idle = false;
    {
      std::lock_guard lock(work.m);
      if (work.error) throw JobFailure(rank, what_of(work.error));
      finished.swap(work.finished);
      outstanding = static_cast<int>(work.queue.size()) + work.busy;
      idle = work.queue.empty() && work.busy == 0;
    }
    for (int item : finished) {
      depth.finished(Clock::now());
      std::vector<char> buffer(sizeof(int));
      std::memcpy(buffer.data(), &item, sizeof(int));
      if (results.pack) results.pack(item, buffer);
      traffic.bytes += buffer.size();
      outbox.send(std::move(buffer), 0, kResult);
      maybe_fail(watch.faults, rank, ++finished_total);
    }
    if (!exhausted && !awaiting && outstanding < depth.target()) {
      want = depth.target() - outstanding;
      traffic.bytes += sizeof(int);
      outbox.send(int_bytes({want}), 0, kRequest);
      awaiting = true;
      asked = Clock::now();
    }
    if (awaiting) {
      int flag = 0;
      check(MPI_Iprobe(0, kItems, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE), "MPI_Iprobe");
      if (flag) {
        std::vector<int> items(static_cast<size_t>(std::max(1, want)));
        check(MPI_Recv(items.data(), static_cast<int>(items.size() * sizeof(int)), MPI_BYTE, 0, kItems, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
              "MPI_Recv");
        std::lock_guard lock(work.m);
        for (int item : items) {
          if (item == kNoMore) exhausted = work.closed = true;
          else work.queue.push_back(item), ++outstanding;
        }
        work.ready.notify_all();
        idle = false;
        awaiting = false;
        heard = true;
        depth.answered(std::chrono::duration<double>(Clock::now() - asked).count());
      } else if (watch.overdue(asked, Clock::now())) {
        throw JobFailure(0, "no answer for " + watch.seconds() + " s to rank " + std::to_string(rank) +
                                "'s request for work; a hung rank? (--rank-timeout)");
      }
    }
    if (outstanding > 0 && Clock::now() - outbox.last_send() >= watch.heartbeat())
      outbox.send(int_bytes({0}), 0, kHeartbeat);
    outbox.poll();
    if (exhausted && idle && finished.empty()) {
      outbox.drain();
      return;
    }
    pause_until_progress(work, pause, heard);
  }
}

void run(LocalWork& work, int count, const QueueDepth& depth, const Results& results, const Watch& watch,
         Traffic& traffic) {
  if (world_rank() == 0) coordinate(work, count, depth, results, watch, traffic);
  else follow(work, depth, results, watch, traffic);
  // No rank starts the next run (the next frame) while rank 0 may still be in
  // this one: it would answer the next run's first request with "no more".
  MPI_Request barrier;
  check(MPI_Ibarrier(MPI_COMM_WORLD, &barrier), "MPI_Ibarrier");
  wait_calmly(barrier, "MPI_Ibarrier");
}

}  // namespace

Session::Session() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  // Worker threads never call MPI, so funneled is all glint needs.
  if (provided < MPI_THREAD_FUNNELED) throw JobFailure(rank, "the MPI library does not support MPI_THREAD_FUNNELED");
}

Session::~Session() { MPI_Finalize(); }

void abort_job(int exit_code) { MPI_Abort(MPI_COMM_WORLD, exit_code); }

std::vector<int> failed_ranks(bool ok) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::vector<int> all(size);
  int mine = ok ? 1 : 0;
  // Ranks load the scene at their own pace: the first to finish waits here.
  MPI_Request request;
  check(MPI_Iallgather(&mine, 1, MPI_INT, all.data(), 1, MPI_INT, MPI_COMM_WORLD, &request), "MPI_Iallgather");
  wait_calmly(request, "MPI_Iallgather");
  std::vector<int> failed;
  for (int r = 0; r < size; ++r)
    if (!all[r]) failed.push_back(r);
  return failed;
}

void broadcast(std::vector<int>& values) {
  int n = static_cast<int>(values.size());
  MPI_Request request;
  check(MPI_Ibcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD, &request), "MPI_Ibcast");
  wait_calmly(request, "MPI_Ibcast");
  values.resize(n);
  check(MPI_Ibcast(values.data(), n, MPI_INT, 0, MPI_COMM_WORLD, &request), "MPI_Ibcast");
  wait_calmly(request, "MPI_Ibcast");
}

namespace {
double cpu_seconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}  // namespace

Image render_image(const Scene& scene, const Accelerator& accel, int threads, int tile_size, DistributedStats* stats,
                   double rank_timeout, const FaultInjection& faults) {
  const auto start = std::chrono::steady_clock::now();
  const double process_cpu = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID), main_cpu = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
  const int w = scene.render.width, h = scene.render.height;
  const int tiles_x = (w + tile_size - 1) / tile_size, tiles_y = (h + tile_size - 1) / tile_size;
  Image image(w, h);
  // A tile travels as its index and its rows of float RGB, exactly the bits
  // rank 0 would have computed itself.
  auto tile_rect = [&](int t, int& x0, int& y0, int& x1, int& y1) {
    x0 = (t % tiles_x) * tile_size, y0 = (t / tiles_x) * tile_size;
    x1 = std::min(x0 + tile_size, w), y1 = std::min(y0 + tile_size, h);
  };
  Results results;
  results.pack = [&](int t, std::vector<char>& bytes) {
    int x0, y0, x1, y1;
    tile_rect(t, x0, y0, x1, y1);
    const size_t row = static_cast<size_t>(x1 - x0) * 3 * sizeof(float), at = bytes.size();
    bytes.resize(at + row * (y1 - y0));
    for (int y = y0; y < y1; ++y) std::memcpy(bytes.data() + at + row * (y - y0), image.pixel(x0, y), row);
  };
  uint64_t pixel_bytes = 0;
  results.unpack = [&](int t, const char* bytes, size_t size) {
    int x0, y0, x1, y1;
    tile_rect(t, x0, y0, x1, y1);
    const size_t row = static_cast<size_t>(x1 - x0) * 3 * sizeof(float);
    if (size != row * (y1 - y0)) throw JobFailure(0, "a tile of the wrong size arrived");  // cannot happen
    pixel_bytes += size;
    for (int y = y0; y < y1; ++y) std::memcpy(image.pixel(x0, y), bytes + row * (y - y0), row);
  };

  LocalWork work;
  TileStream stream;
  stream.tile_size = tile_size;
  stream.next = [&] { return work.pop(); };
  stream.done = [&](int t) { work.finish(t); };
  RayStats rays;
  std::thread renderer([&] {
    try {
      rays = render_tile_stream(scene, accel, image, stream, threads);
    } catch (...) {
      work.fail(std::current_exception());
    }
  });
  const JoinOnExit joined(work, renderer);
  Traffic traffic;
  // Enough queued per rank that no worker waits for a round trip to rank 0
  // (threads + 2 left rank 1's one worker idle 20% of the time on the
  // showcase; QueueDepth adds more when tiles go fast), few enough that a slow
  // rank holds the frame's end back by only a few of its tiles' time (at most
  // 0.1 s of its work).
  run(work, tiles_x * tiles_y, QueueDepth(4 * threads + 4, 64 * threads + 64), results,
      Watch{rank_timeout, "tiles", {}, faults}, traffic);
  renderer.join();

  uint64_t mine[6] = {rays.camera, rays.shadow, rays.reflection, rays.refraction, traffic.bytes, rays.camera_hits},
           sum[6] = {};
  MPI_Request request;
  check(MPI_Ireduce(mine, sum, 6, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD, &request), "MPI_Ireduce");
  wait_calmly(request, "MPI_Ireduce");
  // Each rank's CPU time in this render: the whole process, and of that its main thread's (MPI).
  const double cpu[2] = {cpu_seconds(CLOCK_PROCESS_CPUTIME_ID) - process_cpu,
                         cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - main_cpu};
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::vector<double> cpus(2 * static_cast<size_t>(size));
  check(MPI_Igather(cpu, 2, MPI_DOUBLE, cpus.data(), 2, MPI_DOUBLE, 0, MPI_COMM_WORLD, &request), "MPI_Igather");
  wait_calmly(request, "MPI_Igather");
  if (stats) {
    stats->rays = RayStats{sum[0], sum[1], sum[2], sum[3], sum[5]};
    stats->bytes_sent = sum[4];
    stats->pixel_bytes = pixel_bytes;
    stats->tiles_by_rank = traffic.items_by_rank;
    stats->cpu_by_rank.clear();
    stats->main_cpu_by_rank.clear();
    for (int r = 0; r < size; ++r) {
      stats->cpu_by_rank.push_back(cpus[2 * r]);
      stats->main_cpu_by_rank.push_back(cpus[2 * r + 1]);
    }
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (world_rank() != 0) return Image();
  return image;
}

void run_items(int count, const std::function<void(int item, const std::atomic<bool>& stop)>& render,
               double rank_timeout, const std::function<std::string(int item)>& name, const FaultInjection& faults) {
  LocalWork work;
  std::thread renderer([&] {
    for (int item = work.pop(); item != kNoMore; item = work.pop()) {
      try {
        render(item, work.stopping);
      } catch (...) {
        work.fail(std::current_exception());
        return;
      }
      work.finish(item);
    }
  });
  const JoinOnExit joined(work, renderer);
  Traffic traffic;
  // One frame at a time: it uses all the rank's threads.
  run(work, count, QueueDepth(1, 1), Results{}, Watch{rank_timeout, "frames", name, faults}, traffic);
  renderer.join();
}

}  // namespace glint::mpi
