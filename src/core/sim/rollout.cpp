// A batch of simulations stepped by a pool of threads. Declared and
// documented in endovascular_sim/sim/rollout.h.
#include "endovascular_sim/sim/rollout.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace evsim {

namespace {

/// Threads kept between batches (a thread's caches, core/thread_cache.h,
/// stay warm: a vector environment's batch is a few steps long). run()
/// calls task(i) for every i in [0, n) on up to `threads` threads, the
/// caller's among them, and returns when all are done. A second caller
/// while a batch runs steps its own on its thread alone.
class WorkerPool {
 public:
  static WorkerPool& instance() {
    static WorkerPool* pool = new WorkerPool;  // never destroyed: its threads wait until exit
    return *pool;
  }

  void run(long n, int threads, const std::function<void(long)>& task) {
    std::unique_lock<std::mutex> batch(batch_, std::try_to_lock);
    if (!batch.owns_lock() || threads <= 1) {
      for (long i = 0; i < n; ++i) task(i);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      while (static_cast<int>(workers_.size()) < threads - 1)
        workers_.emplace_back([this, k = static_cast<int>(workers_.size())] { serve(k); });
      task_ = &task;
      count_ = n;
      next_ = 0;
      helpers_ = threads - 1;
      busy_ = helpers_;
      error_ = nullptr;
      ++generation_;
    }
    wake_.notify_all();
    work();
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return busy_ == 0; });
    task_ = nullptr;
    if (error_) std::rethrow_exception(error_);
  }

 private:
  void work() {
    for (long i = next_++; i < count_; i = next_++) {
      try {
        (*task_)(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!error_) error_ = std::current_exception();
      }
    }
  }

  void serve(int index) {
    unsigned seen = 0;
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return generation_ != seen; });
        seen = generation_;
        if (index >= helpers_) continue;  // not wanted for this batch
      }
      work();
      std::lock_guard<std::mutex> lock(mutex_);
      if (--busy_ == 0) done_.notify_one();
    }
  }

  std::mutex batch_;  // one batch at a time
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  const std::function<void(long)>* task_{nullptr};
  std::atomic<long> next_{0};
  long count_{0};
  int helpers_{0};
  int busy_{0};
  unsigned generation_{0};
  std::exception_ptr error_;
};

int totalNodes(const SceneModel& model) {
  int n = 0;
  for (const DeviceModel& d : model.devices) n += d.num_nodes;
  return n;
}

/// Takes the step's forces into the peaks of simulation n's command t.
void notePeaks(const SimData& data, long nt, RolloutOutput* out) {
  out->max_wall_force[nt] = std::max(out->max_wall_force[nt], maxWallForce(data));
  for (int d = 0; d < out->devices && d < static_cast<int>(data.drives.size()); ++d) {
    double& peak = out->peak_drive_force[static_cast<size_t>(nt) * out->devices + d];
    peak = std::max(peak, std::abs(data.drives[d].axial_force));
  }
}

/// Records simulation n's state after command t.
void record(const SceneModel& model, const SimData& data, long n, long t, bool failed,
            RolloutOutput* out) {
  const long nt = n * out->horizon + t;
  const int nd = out->devices;
  out->time[nt] = data.time;
  out->failed[nt] = failed ? 1 : 0;
  double* node = &out->node_position[static_cast<size_t>(nt) * out->nodes * 3];
  for (int d = 0; d < nd; ++d) {
    const DeviceState& s = data.devices[d];
    for (const Vec3& x : s.position) {
      node[0] = x.x(), node[1] = x.y(), node[2] = x.z();
      node += 3;
    }
    const size_t k = static_cast<size_t>(nt) * nd + d;
    const Vec3& tip = s.position.back();
    for (int c = 0; c < 3; ++c) out->tip_position[k * 3 + c] = tip(c);
    out->inserted_length[k] = s.inserted_length;
    out->rotation_angle[k] = s.rotation_angle;
    out->drive_force[k] = d < static_cast<int>(data.drives.size()) ? data.drives[d].axial_force : 0.0;
    out->tip_vessel[k] = model.atlas && d < static_cast<int>(data.tips.size()) ? data.tips[d].vessel : -1;
  }
}

/// Steps simulation n through its T commands.
void rollOne(const SceneModel& model, SimData* data, const double* commands, long n,
             long steps_per_command, bool recover, RolloutOutput* out) {
  const int nd = out->devices;
  bool failed = false;
  for (long t = 0; t < out->horizon; ++t) {
    if (!failed) {
      const double* c = commands + (n * out->horizon + t) * 2 * nd;
      for (int d = 0; d < nd; ++d)
        applyCommand(data, d, DriveCommand{DriveCommand::Mode::kVelocity, c[2 * d], c[2 * d + 1]});
      for (long k = 0; k < steps_per_command && !failed; ++k) {
        bool recovered = false;
        const StepStatus status = recover ? stepOrRecover(model, data, &recovered)
                                          : step(model, data);
        failed = status != StepStatus::kOk;
        if (!failed) notePeaks(*data, n * out->horizon + t, out);
      }
    }
    record(model, *data, n, t, failed, out);
  }
}

}  // namespace

std::string checkRollout(const std::vector<const SceneModel*>& models,
                         const std::vector<SimData*>& data, const double* commands, long horizon,
                         long steps_per_command) {
  std::ostringstream why;
  if (models.size() != data.size() && models.size() != 1) {
    why << models.size() << " models for " << data.size()
        << " simulations: give one model, or one per simulation";
    return why.str();
  }
  if (horizon < 0 || steps_per_command < 1) {
    why << "the horizon (" << horizon << ") must not be negative and the steps per command ("
        << steps_per_command << ") at least 1";
    return why.str();
  }
  const SceneModel& first = *models.front();
  for (size_t n = 0; n < data.size(); ++n) {
    const SceneModel& m = *models[models.size() == 1 ? 0 : n];
    if (m.devices.size() != first.devices.size()) {
      why << "simulation " << n << " has " << m.devices.size() << " devices, simulation 0 "
          << first.devices.size() << ": a batch's simulations drive as many devices";
      return why.str();
    }
    if (data[n]->devices.size() != m.devices.size()) {
      why << "simulation " << n << "'s data were not made for its model ('" << m.name << "')";
      return why.str();
    }
    for (size_t d = 0; d < m.devices.size(); ++d)
      if (static_cast<int>(data[n]->devices[d].position.size()) != m.devices[d].num_nodes) {
        why << "simulation " << n << "'s data were not made for its model ('" << m.name << "')";
        return why.str();
      }
    const int nd = static_cast<int>(m.devices.size());
    for (long t = 0; t < horizon; ++t)
      for (int d = 0; d < nd; ++d) {
        const double* c = commands + (n * horizon + t) * 2 * nd + 2 * d;
        const std::string bad =
            validateDriveCommand({DriveCommand::Mode::kVelocity, c[0], c[1]}, m.devices[d]);
        if (!bad.empty()) {
          why << "commands[" << n << ", " << t << "] for device '" << m.devices[d].name
              << "': " << bad;
          return why.str();
        }
      }
  }
  return "";
}

RolloutOutput rollout(const std::vector<const SceneModel*>& models,
                      const std::vector<SimData*>& data, const double* commands, long horizon,
                      long steps_per_command, int threads, bool recover) {
  if (models.empty() || data.empty()) return {};
  const std::string why = checkRollout(models, data, commands, horizon, steps_per_command);
  if (!why.empty()) throw std::invalid_argument(why);
  RolloutOutput out;
  out.batch = static_cast<long>(data.size());
  out.horizon = horizon;
  out.devices = static_cast<int>(models.front()->devices.size());
  out.nodes = totalNodes(*models.front());
  for (const SceneModel* m : models) out.nodes = std::max(out.nodes, totalNodes(*m));
  const size_t nt = static_cast<size_t>(out.batch * horizon);
  out.time.assign(nt, 0.0);
  out.failed.assign(nt, 0);
  out.max_wall_force.assign(nt, 0.0);
  out.node_position.assign(nt * out.nodes * 3, std::nan(""));
  out.tip_position.assign(nt * out.devices * 3, 0.0);
  out.inserted_length.assign(nt * out.devices, 0.0);
  out.rotation_angle.assign(nt * out.devices, 0.0);
  out.drive_force.assign(nt * out.devices, 0.0);
  out.peak_drive_force.assign(nt * out.devices, 0.0);
  out.tip_vessel.assign(nt * out.devices, -1);

  const std::function<void(long)> task = [&](long n) {
    rollOne(*models[models.size() == 1 ? 0 : n], data[n], commands, n, steps_per_command, recover,
            &out);
  };
  WorkerPool::instance().run(out.batch, std::clamp(threads, 1, static_cast<int>(out.batch)), task);
  return out;
}

}  // namespace evsim
