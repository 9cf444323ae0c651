#include "glint/render/distributed.h"

#include <mpi.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "glint/error.h"
#include "glint/render/tile_stream.h"

namespace glint::mpi {

namespace {

enum Tag : int { kRequest = 101, kItems = 102, kResult = 103 };
constexpr int kNoMore = -1;

int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

// With MPI_ERRORS_RETURN a failed call comes back here: say which rank and
// what, then end the job rather than wait for a message that will not come.
void check(int rc, const char* call) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(rc, text, &length);
  abort_job(world_rank(), std::string(call) + " failed: " + std::string(text, length));
}

// One rank's share of the work: items from rank 0, taken by worker threads.
struct LocalWork {
  std::mutex m;
  std::condition_variable ready;  // workers wait for items
  std::condition_variable wake;   // the main thread waits for finished items
  std::deque<int> queue;
  bool closed = false;  // no more items will come
  int busy = 0;         // taken by a worker, not finished
  std::vector<int> finished;  // not yet reported by the main thread
  std::exception_ptr error;

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
};

// What a finished item sends to rank 0, and what rank 0 does with it; no
// `pack`: items send nothing (frames, written by the rank that renders them).
struct Results {
  std::function<std::vector<char>(int item)> pack;
  std::function<void(const std::vector<char>&)> unpack;
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

// Test hook (GLINT_TEST_DIE_RANK=R): rank R kills itself after its first
// finished item, to check how the job fails when a rank dies.
void maybe_die(int rank, int finished) {
  static const char* die = std::getenv("GLINT_TEST_DIE_RANK");
  if (die && finished > 0 && std::atoi(die) == rank) raise(SIGKILL);
}

// Waits until a local item finishes (workers wake us), or up to `pause` so
// that messages from other ranks are polled. The pause doubles while no
// message comes (250 us to 2 ms): polling takes little CPU from the workers,
// and each rank's queue of tiles covers a round trip to rank 0.
constexpr auto kMinPause = std::chrono::microseconds(250), kMaxPause = std::chrono::microseconds(2000);
void pause_until_progress(LocalWork& work, std::chrono::microseconds& pause, bool heard) {
  pause = heard ? kMinPause : std::min(pause * 2, kMaxPause);
  std::unique_lock lock(work.m);
  work.wake.wait_for(lock, pause, [&] { return !work.finished.empty() || work.error; });
}

struct Traffic {
  uint64_t bytes = 0;
  std::vector<int> items_by_rank;
};

// Rank 0's main thread: hands out items 0..count-1 (to its own queue and on
// request to other ranks), takes results, until every item is done and every
// other rank has been told there is no more work.
void coordinate(LocalWork& work, int count, int depth, const Results& results, Traffic& traffic) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  traffic.items_by_rank.assign(size, 0);
  int next = 0, done = 0, ranks_told = 0;
  auto pause = kMinPause;
  for (;;) {
    bool heard = false;  // a message from another rank
    int flag = 0;
    MPI_Status status;
    for (check(MPI_Iprobe(MPI_ANY_SOURCE, kRequest, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe"); flag;
         check(MPI_Iprobe(MPI_ANY_SOURCE, kRequest, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe")) {
      int want = 0;
      check(MPI_Recv(&want, 1, MPI_INT, status.MPI_SOURCE, kRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
      std::vector<int> items(std::max(1, want), kNoMore);
      for (int& item : items)
        if (next < count) item = next++;
      if (items.back() == kNoMore) ++ranks_told;  // that rank asks no more
      check(MPI_Send(items.data(), static_cast<int>(items.size()), MPI_INT, status.MPI_SOURCE, kItems, MPI_COMM_WORLD),
            "MPI_Send");
      traffic.bytes += items.size() * sizeof(int);
      heard = true;
    }
    for (check(MPI_Iprobe(MPI_ANY_SOURCE, kResult, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe"); flag;
         check(MPI_Iprobe(MPI_ANY_SOURCE, kResult, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe")) {
      int bytes = 0;
      MPI_Get_count(&status, MPI_BYTE, &bytes);
      std::vector<char> buffer(bytes);
      check(MPI_Recv(buffer.data(), bytes, MPI_BYTE, status.MPI_SOURCE, kResult, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "MPI_Recv");
      results.unpack(buffer);
      ++done;
      ++traffic.items_by_rank[status.MPI_SOURCE];
      heard = true;
    }
    bool idle = false;
    {
      std::lock_guard lock(work.m);
      if (work.error) abort_job(0, what_of(work.error));
      while (static_cast<int>(work.queue.size()) + work.busy < depth && next < count) work.queue.push_back(next++);
      if (next >= count) work.closed = true;
      work.ready.notify_all();
      traffic.items_by_rank[0] += static_cast<int>(work.finished.size());
      done += static_cast<int>(work.finished.size());
      maybe_die(0, static_cast<int>(work.finished.size()));
      work.finished.clear();
      idle = work.closed && work.queue.empty() && work.busy == 0;
    }
    // Frames (no results) are done when this rank's own are; other ranks
    // finish theirs on their own.
    const bool all_done = results.pack ? done == count : idle;
    if (all_done && idle && ranks_told == size - 1) return;
    pause_until_progress(work, pause, heard);
  }
}

// Every other rank's main thread: keeps `depth` items queued or in work,
// asking rank 0 for more, and sends each finished item's result.
void follow(LocalWork& work, int depth, const Results& results, Traffic& traffic) {
  const int rank = world_rank();
  bool exhausted = false, awaiting = false;
  int want = 0, finished_total = 0;
  auto pause = kMinPause;
  for (;;) {
    bool heard = false;  // the reply from rank 0
    std::vector<int> finished;
    int outstanding = 0;
    bool idle = false;
    {
      std::lock_guard lock(work.m);
      if (work.error) abort_job(rank, what_of(work.error));
      finished.swap(work.finished);
      outstanding = static_cast<int>(work.queue.size()) + work.busy;
      idle = work.queue.empty() && work.busy == 0;
    }
    for (int item : finished) {
      if (results.pack) {
        const std::vector<char> buffer = results.pack(item);
        check(MPI_Send(buffer.data(), static_cast<int>(buffer.size()), MPI_BYTE, 0, kResult, MPI_COMM_WORLD),
              "MPI_Send");
        traffic.bytes += buffer.size();
      }
      maybe_die(rank, ++finished_total);
    }
    if (!exhausted && !awaiting && outstanding < depth) {
      want = depth - outstanding;
      check(MPI_Send(&want, 1, MPI_INT, 0, kRequest, MPI_COMM_WORLD), "MPI_Send");
      traffic.bytes += sizeof(int);
      awaiting = true;
    }
    if (awaiting) {
      int flag = 0;
      check(MPI_Iprobe(0, kItems, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE), "MPI_Iprobe");
      if (flag) {
        std::vector<int> items(std::max(1, want));
        check(MPI_Recv(items.data(), static_cast<int>(items.size()), MPI_INT, 0, kItems, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
              "MPI_Recv");
        std::lock_guard lock(work.m);
        for (int item : items) {
          if (item == kNoMore) exhausted = work.closed = true;
          else work.queue.push_back(item);
        }
        work.ready.notify_all();
        idle = false;
        awaiting = false;
        heard = true;
      }
    }
    if (exhausted && idle && finished.empty()) return;
    pause_until_progress(work, pause, heard);
  }
}

void run(LocalWork& work, int count, int depth, const Results& results, Traffic& traffic) {
  if (world_rank() == 0) coordinate(work, count, depth, results, traffic);
  else follow(work, depth, results, traffic);
  // No rank starts the next run (the next frame) while rank 0 may still be in
  // this one: it would answer the next run's first request with "no more".
  check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
}

}  // namespace

bool launched() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

Session::Session() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  // Worker threads never call MPI, so funneled is all glint needs.
  if (provided < MPI_THREAD_FUNNELED) abort_job(rank, "the MPI library does not support MPI_THREAD_FUNNELED");
}

Session::~Session() { MPI_Finalize(); }

void abort_job(int rank, const std::string& what) {
  std::fprintf(stderr, "error: rank %d: %s\n", rank, what.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 1);
  std::_Exit(1);
}

std::vector<int> failed_ranks(bool ok) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::vector<int> all(size);
  int mine = ok ? 1 : 0;
  check(MPI_Allgather(&mine, 1, MPI_INT, all.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
  std::vector<int> failed;
  for (int r = 0; r < size; ++r)
    if (!all[r]) failed.push_back(r);
  return failed;
}

void broadcast(std::vector<int>& values) {
  int n = static_cast<int>(values.size());
  check(MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast");
  values.resize(n);
  check(MPI_Bcast(values.data(), n, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast");
}

Image render_image(const Scene& scene, const Accelerator& accel, int threads, int tile_size,
                   DistributedStats* stats) {
  const auto start = std::chrono::steady_clock::now();
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
  results.pack = [&](int t) {
    int x0, y0, x1, y1;
    tile_rect(t, x0, y0, x1, y1);
    const size_t row = static_cast<size_t>(x1 - x0) * 3 * sizeof(float);
    std::vector<char> buffer(sizeof(int) + row * (y1 - y0));
    std::memcpy(buffer.data(), &t, sizeof(int));
    for (int y = y0; y < y1; ++y) std::memcpy(buffer.data() + sizeof(int) + row * (y - y0), image.pixel(x0, y), row);
    return buffer;
  };
  uint64_t pixel_bytes = 0;
  results.unpack = [&](const std::vector<char>& buffer) {
    pixel_bytes += buffer.size() - sizeof(int);
    int t = 0;
    std::memcpy(&t, buffer.data(), sizeof(int));
    int x0, y0, x1, y1;
    tile_rect(t, x0, y0, x1, y1);
    const size_t row = static_cast<size_t>(x1 - x0) * 3 * sizeof(float);
    for (int y = y0; y < y1; ++y) std::memcpy(image.pixel(x0, y), buffer.data() + sizeof(int) + row * (y - y0), row);
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
  Traffic traffic;
  // Enough queued per rank that no worker waits for a round trip to rank 0
  // (up to two polling pauses, a few tiles' time: threads + 2 left rank 1's
  // one worker idle 20% of the time on the showcase), few enough that a slow
  // rank holds the frame's end back by only a few of its tiles' time.
  run(work, tiles_x * tiles_y, 4 * threads + 4, results, traffic);
  renderer.join();

  uint64_t mine[5] = {rays.camera, rays.shadow, rays.reflection, rays.refraction, traffic.bytes}, sum[5] = {};
  check(MPI_Reduce(mine, sum, 5, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD), "MPI_Reduce");
  if (stats) {
    stats->rays = RayStats{sum[0], sum[1], sum[2], sum[3]};
    stats->bytes_sent = sum[4];
    stats->pixel_bytes = pixel_bytes;
    stats->tiles_by_rank = traffic.items_by_rank;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (world_rank() != 0) return Image();
  return image;
}

void run_items(int count, const std::function<void(int item)>& render) {
  LocalWork work;
  std::thread renderer([&] {
    for (int item = work.pop(); item != kNoMore; item = work.pop()) {
      try {
        render(item);
      } catch (...) {
        work.fail(std::current_exception());
        return;
      }
      work.finish(item);
    }
  });
  Traffic traffic;
  run(work, count, 1, Results{}, traffic);  // one frame at a time: it uses all the rank's threads
  renderer.join();
}

}  // namespace glint::mpi
