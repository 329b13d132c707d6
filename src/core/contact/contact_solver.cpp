#include "endovascular_sim/contact/contact_solver.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "endovascular_sim/contact/delassus.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/mechanics/elasticity.h"

namespace evsim {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Configuration x_t (+) dq for every device.
std::vector<DeviceState> moved(const std::vector<DeviceState>& start, const std::vector<VecX>& dq) {
  std::vector<DeviceState> x = start;
  for (size_t d = 0; d < x.size(); ++d) applyIncrement(dq[d], 0, &x[d]);
  return x;
}

/// True when the sample point moves with at least one free node.
bool isFree(const SamplePoint& s, int first_free) {
  if (s.xi == 0.0) return s.element >= first_free;
  return s.element + 1 >= first_free;
}

/// Depth beyond the surface [m] (0 inside), from g / |grad g|.
double depthOf(const FieldSample& g) {
  if (g.value >= 0.0) return 0.0;
  const double n = g.gradient.norm();
  return n > 0.0 ? -g.value / n : 0.0;
}

}  // namespace

bool writeLcpRecord(const LcpRecord& r, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  const long c = r.q.size();
  std::fprintf(f,
               "# endovascular_sim LCP: w = W z + q, 0 <= z _|_ w >= 0; W [m/N], q [m], z [N]\n");
  std::fprintf(f, "size %ld\nW\n", c);
  for (long i = 0; i < c; ++i)
    for (long j = 0; j < c; ++j) std::fprintf(f, "%.17g%c", r.W(i, j), j + 1 < c ? ' ' : '\n');
  std::fprintf(f, "q\n");
  for (long i = 0; i < c; ++i) std::fprintf(f, "%.17g\n", r.q(i));
  std::fprintf(f, "z\n");
  for (long i = 0; i < c; ++i) std::fprintf(f, "%.17g\n", r.z(i));
  return std::fclose(f) == 0;
}

LcpRecord readLcpRecord(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw LoadError(path, 0, "", "cannot open the LCP file");
  std::string line, word;
  std::getline(in, line);  // header comment
  long c = -1;
  if (!(in >> word >> c) || word != "size" || c < 0)
    throw LoadError(path, 2, "size", "expected 'size c'");
  LcpRecord r{MatX(c, c), VecX(c), VecX(c)};
  auto expect = [&](const char* name) {
    if (!(in >> word) || word != name) throw LoadError(path, 0, name, "section missing");
  };
  expect("W");
  for (long i = 0; i < c * c; ++i)
    if (!(in >> r.W(i / c, i % c))) throw LoadError(path, 0, "W", "too few numbers");
  expect("q");
  for (long i = 0; i < c; ++i)
    if (!(in >> r.q(i))) throw LoadError(path, 0, "q", "too few numbers");
  expect("z");
  for (long i = 0; i < c; ++i)
    if (!(in >> r.z(i))) throw LoadError(path, 0, "z", "too few numbers");
  return r;
}

std::string validateContactOptions(const ContactOptions& o) {
  std::ostringstream why;
  if (!(o.lcp.tolerance > 0.0 && o.lcp.tolerance <= 1e-3))
    why << "lcp tolerance must lie in (0, 1e-3] m";
  else if (o.lcp.max_iterations < 0 || o.lcp.max_iterations > 1000000)
    why << "lcp max_iterations must lie in [0, 1e6] (0: automatic)";
  else if (!(o.lcp.regularization >= 0.0 && o.lcp.regularization <= 1e-3))
    why << "lcp regularization must lie in [0, 1e-3]";
  else if (o.max_activation_loops < 1 || o.max_activation_loops > 1000)
    why << "max_activation_loops must lie in [1, 1000]";
  else if (o.max_subdivisions < 0 || o.max_subdivisions > 12)
    why << "max_subdivisions must lie in [0, 12]";
  else if (!(o.contact_spacing >= 1e-5 && o.contact_spacing <= 0.05))
    why << "contact_spacing must lie in [1e-5, 0.05] m";
  else if (!(o.penetration_tolerance >= 1e-9 && o.penetration_tolerance <= 1e-3))
    why << "penetration_tolerance must lie in [1e-9, 1e-3] m";
  else if (!(o.root.tolerance > 0.0 && o.root.tolerance <= 1e-6))
    why << "root tolerance must lie in (0, 1e-6] m";
  return why.str();
}

bool resolveContacts(const ContactProblem& pb, const ContactOptions& o,
                     std::vector<Contact>* contacts, ContactStats* st) {
  const auto& devices = *pb.devices;
  const auto& start = *pb.start;
  auto& ws = *pb.workspaces;
  const auto& samples = *pb.samples;
  const size_t nd = devices.size();
  contacts->clear();
  *st = ContactStats{};

  // --- Detection on [x_t, x_f] -------------------------------------------
  auto t0 = Clock::now();
  std::vector<VecX> dq_free(nd), dq(nd);
  for (size_t d = 0; d < nd; ++d) dq_free[d] = dq[d] = ws[d].dq;
  const std::vector<DeviceState> xf = moved(start, dq_free);
  std::vector<std::vector<int>> contact_of(nd);  // sample -> contact index or -1
  for (size_t d = 0; d < nd; ++d) {
    contact_of[d].assign(samples[d].size(), -1);
    const int first_free = ws[d].first_free_node;
    // Per element, the deepest crossing at x_f only: the activation loop adds
    // any other point of the element that stays beyond the wall.
    int best_element = -1, best_sample = -1;
    double best_depth = -1.0;
    SurfacePoint best_hit;
    auto flush = [&]() {
      if (best_sample < 0) return;
      contact_of[d][best_sample] = static_cast<int>(contacts->size());
      contacts->push_back(
          {static_cast<int>(d), best_sample, best_hit.point, best_hit.normal, 0, 0});
      best_sample = -1;
      best_depth = -1.0;
    };
    for (size_t k = 0; k < samples[d].size(); ++k) {
      const SamplePoint& s = samples[d][k];
      if (s.element != best_element) {
        flush();
        best_element = s.element;
      }
      if (!isFree(s, first_free)) continue;
      const Vec3 p0 = samplePosition(devices[d], start[d], s);
      const Vec3 p1 = samplePosition(devices[d], xf[d], s);
      SurfacePoint hit = firstRoot(*pb.surface, p0, p1, s.radius, pb.motion, o.root);
      if (!hit.hit) continue;
      if (hit.started_outside) {  // already beyond the wall (moving wall, tolerance)
        hit = projectToSurface(*pb.surface, p1, s.radius, pb.motion, 0.01, o.root);
        if (!hit.hit) continue;
      }
      const double depth = -hit.normal.dot(p1 - hit.point);
      if (depth > best_depth) {
        best_depth = depth;
        best_sample = static_cast<int>(k);
        best_hit = hit;
      }
    }
    flush();
  }
  st->detection_ms += msSince(t0);

  bool solved = contacts->empty();
  std::vector<DeviceState> x = xf;
  std::vector<char> updated(contacts->size(), 0);  // plane already updated in this step
  for (int loop = 1; loop <= o.max_activation_loops && !solved; ++loop) {
    st->activation_loops = loop;
    const int c = static_cast<int>(contacts->size());

    // --- Delassus operator W = H A^-1 H^T, q = H x_f - delta ---------------
    t0 = Clock::now();
    MatX W = MatX::Zero(c, c);
    VecX q(c);
    std::vector<std::vector<int>> of_device(nd);
    std::vector<Row12> rows(c);
    for (int i = 0; i < c; ++i) {
      const Contact& ct = (*contacts)[i];
      const SamplePoint& s = samples[ct.device][ct.sample];
      of_device[ct.device].push_back(i);
      rows[i] = contactRow(devices[ct.device], xf[ct.device], s, ct.normal);
      q(i) = ct.normal.dot(samplePosition(devices[ct.device], xf[ct.device], s) - ct.point);
    }
    std::vector<MatX> Y(nd);  // A^-1 H^T per device (free DOFs x its contacts)
    for (size_t d = 0; d < nd; ++d) {
      const auto& idx = of_device[d];
      if (idx.empty()) continue;
      std::vector<ContactRow> device_rows(idx.size());
      for (size_t j = 0; j < idx.size(); ++j) {
        const SamplePoint& s = samples[d][(*contacts)[idx[j]].sample];
        device_rows[j] = {6 * (s.element - ws[d].first_free_node), rows[idx[j]]};
      }
      MatX Wd;
      delassusOperator(ws[d].cholesky, device_rows, &Y[d], &Wd);
      for (size_t a = 0; a < idx.size(); ++a)
        for (size_t b = 0; b < idx.size(); ++b) W(idx[a], idx[b]) = Wd(a, b);
    }
    st->delassus_ms += msSince(t0);

    // --- Status method (or the chosen solver) -------------------------------
    t0 = Clock::now();
    VecX lambda;
    LcpStats ls;
    const LcpStatus status = solveLcp(W, q, o.lcp, &lambda, &ls);
    st->lcp_ms += msSince(t0);
    st->lcp_iterations += ls.iterations;
    st->lcp_residual = ls.residual;
    st->contacts = c;
    if (pb.record) *pb.record = {W, q, lambda};
    if (status != LcpStatus::kSolved) return false;  // the caller subdivides

    // --- Correction x = x_f + A^-1 H^T lambda --------------------------------
    t0 = Clock::now();
    for (size_t d = 0; d < nd; ++d) {
      dq[d] = dq_free[d];
      const auto& idx = of_device[d];
      if (idx.empty()) continue;
      VecX l(idx.size());
      for (size_t j = 0; j < idx.size(); ++j) l(j) = lambda(idx[j]);
      const int n = ws[d].cholesky.size();
      dq[d].tail(n) += Y[d] * l;
    }
    x = moved(start, dq);
    for (int i = 0; i < c; ++i) (*contacts)[i].force = lambda(i);
    st->correction_ms += msSince(t0);

    // --- Re-detection on x: plane updates and new contacts ------------------
    t0 = Clock::now();
    solved = true;
    for (size_t d = 0; d < nd; ++d) {
      const int first_free = ws[d].first_free_node;
      for (size_t k = 0; k < samples[d].size(); ++k) {
        const SamplePoint& s = samples[d][k];
        if (!isFree(s, first_free)) continue;
        const Vec3 p = samplePosition(devices[d], x[d], s);
        const FieldSample g = pb.surface->evaluate(p, s.radius, pb.motion);
        if (depthOf(g) <= o.penetration_tolerance) continue;
        solved = false;
        SurfacePoint plane = projectToSurface(*pb.surface, p, s.radius, pb.motion, 0.01, o.root);
        const int existing = contact_of[d][k];
        if (existing >= 0 && !updated[existing]) {
          // The paper's update: the tangent plane where x projects.
          if (!plane.hit) continue;
          Contact& ct = (*contacts)[existing];
          ct.point = plane.point;
          ct.normal = plane.normal;
          updated[existing] = 1;
          continue;
        }
        if (existing < 0) {
          const Vec3 p0 = samplePosition(devices[d], start[d], s);
          SurfacePoint hit = firstRoot(*pb.surface, p0, p, s.radius, pb.motion, o.root);
          if (hit.hit && !hit.started_outside) plane = hit;
        }
        // A new contact, or a second plane for a point violated again after
        // its update (a concave wall: updates alone can oscillate; the extra
        // plane only shrinks the admissible set, so the loop converges).
        if (!plane.hit) continue;
        contact_of[d][k] = static_cast<int>(contacts->size());
        contacts->push_back(
            {static_cast<int>(d), static_cast<int>(k), plane.point, plane.normal, 0, 0});
        updated.push_back(0);
      }
    }
    st->detection_ms += msSince(t0);
  }

  // Final gaps, forces, deepest point.
  for (auto& ct : *contacts) {
    const SamplePoint& s = samples[ct.device][ct.sample];
    ct.gap = ct.normal.dot(samplePosition(devices[ct.device], x[ct.device], s) - ct.point);
    if (ct.force > 0.0) ++st->active_contacts;
  }
  for (size_t d = 0; d < nd; ++d) {
    for (const SamplePoint& s : samples[d]) {
      if (!isFree(s, ws[d].first_free_node)) continue;
      const Vec3 p = samplePosition(devices[d], x[d], s);
      st->max_penetration_m =
          std::max(st->max_penetration_m, depthOf(pb.surface->evaluate(p, s.radius, pb.motion)));
    }
    ws[d].dq = dq[d];
  }
  return solved;
}

}  // namespace evsim
