// sphere_fit.cpp — Wang et al. 2006's variational sphere-set fit (see
// sphere_fit.h) and the fit's measurement.
#include "sphere_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <queue>
#include <set>
#include <stdexcept>
#include <tuple>

#include "mesh_geometry.h"

namespace atmo::spheres {

namespace {

std::string format(const char* fmt, double a = 0, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

// A regular lattice centred on [lo, hi]: n points `step` apart.
struct Axis {
  double origin = 0.0;
  int n = 1;
};
Axis centred_axis(double lo, double hi, double step) {
  Axis a;
  a.n = std::max(1, static_cast<int>(std::ceil((hi - lo) / step)));
  a.origin = 0.5 * (lo + hi) - 0.5 * (a.n - 1) * step;
  return a;
}

// Everything the fit knows of the object: sample points, their neighbour
// graph, and the inside rows its outside volumes are integrated on.
class Problem {
 public:
  Problem(const TriangleMesh& mesh, const FitOptions& options) : options_(options) {
    bounds_ = mesh_bounds(mesh);
    step_m_ = bounds_.longest_side_m() / options.grid;
    row_step_m_ = 0.5 * step_m_;
    const glm::dvec3 lo = bounds_.min_m, hi = bounds_.max_m;

    // Energy rows: half the grid step in y and z.
    row_x_ = centred_axis(lo.x, hi.x, row_step_m_);
    const Axis ry = centred_axis(lo.y, hi.y, row_step_m_), rz = centred_axis(lo.z, hi.z, row_step_m_);
    rows_ = inside_rows(mesh, ry.origin, rz.origin, row_step_m_, ry.n, rz.n);

    // Interior samples: cell centres of the grid that are inside.
    const Axis gx = centred_axis(lo.x, hi.x, step_m_), gy = centred_axis(lo.y, hi.y, step_m_),
               gz = centred_axis(lo.z, hi.z, step_m_);
    const InsideRows grid_rows = inside_rows(mesh, gy.origin, gz.origin, step_m_, gy.n, gz.n);
    interior_count_ = append_inside_points(grid_rows, gx, step_m_, points_);
    if (interior_count_ == 0 && signed_volume_m3(mesh) <= 0.0)
      throw std::runtime_error("the mesh has no inside (is it closed and outward-facing?)");
    const std::vector<glm::dvec3> surface = sample_surface(mesh, options.surface_points, options.seed);
    points_.insert(points_.end(), surface.begin(), surface.end());
    points_.insert(points_.end(), mesh.vertices.begin(), mesh.vertices.end());
    build_neighbours();
  }

  // Appends the lattice points (x: `ax`, rows: `rows`) inside the mesh.
  static size_t append_inside_points(const InsideRows& rows, const Axis& ax, double step, std::vector<glm::dvec3>& out) {
    size_t count = 0;
    for (int k = 0; k < rows.nz; ++k)
      for (int j = 0; j < rows.ny; ++j)
        for (const Interval& in : *rows.row(j, k)) {
          const int i0 = std::max(0, static_cast<int>(std::ceil((in.x0_m - ax.origin) / step)));
          for (int i = i0;; ++i) {
            const double x = ax.origin + i * step;
            if (x >= in.x1_m) break;
            if (x < in.x0_m) continue;
            out.push_back({x, rows.y0_m + j * rows.step_m, rows.z0_m + k * rows.step_m});
            ++count;
          }
        }
    return count;
  }

  // V(S \ O) for the sphere (c, r), on the rows: each row's chord less the
  // part of it inside the mesh, times the row's area. Rows beyond the stored
  // ones have nothing inside.
  double outside_volume_m3(const glm::dvec3& c, double r) const {
    const double s = row_step_m_;
    const int j0 = static_cast<int>(std::ceil((c.y - r - rows_.y0_m) / s));
    const int j1 = static_cast<int>(std::floor((c.y + r - rows_.y0_m) / s));
    const int k0 = static_cast<int>(std::ceil((c.z - r - rows_.z0_m) / s));
    const int k1 = static_cast<int>(std::floor((c.z + r - rows_.z0_m) / s));
    const double r2 = r * r;
    double sum = 0.0;
    for (int k = k0; k <= k1; ++k) {
      const double dz = rows_.z0_m + k * s - c.z;
      for (int j = j0; j <= j1; ++j) {
        const double dy = rows_.y0_m + j * s - c.y;
        const double d2 = dy * dy + dz * dz;
        if (d2 >= r2) continue;
        const double half = std::sqrt(r2 - d2);
        const std::vector<Interval>* row = rows_.row(j, k);
        sum += 2.0 * half - (row ? overlap_length_m(*row, c.x - half, c.x + half) : 0.0);
      }
    }
    return sum * s * s;
  }

  // The sphere's volume covered by other spheres, as a fraction of its own (on the rows).
  double overlap_fraction(const std::vector<Sphere>& spheres, const std::vector<bool>& live, size_t i) const {
    const Sphere& a = spheres[i];
    const double s = row_step_m_, r2 = a.radius_m * a.radius_m;
    const int j0 = static_cast<int>(std::ceil((a.centre_m.y - a.radius_m - rows_.y0_m) / s));
    const int j1 = static_cast<int>(std::floor((a.centre_m.y + a.radius_m - rows_.y0_m) / s));
    const int k0 = static_cast<int>(std::ceil((a.centre_m.z - a.radius_m - rows_.z0_m) / s));
    const int k1 = static_cast<int>(std::floor((a.centre_m.z + a.radius_m - rows_.z0_m) / s));
    double own = 0.0, shared = 0.0;
    std::vector<Interval> others;
    for (int k = k0; k <= k1; ++k) {
      const double z = rows_.z0_m + k * s;
      for (int j = j0; j <= j1; ++j) {
        const double y = rows_.y0_m + j * s;
        const double d2 = (y - a.centre_m.y) * (y - a.centre_m.y) + (z - a.centre_m.z) * (z - a.centre_m.z);
        if (d2 >= r2) continue;
        const double half = std::sqrt(r2 - d2);
        others.clear();
        for (size_t o = 0; o < spheres.size(); ++o) {
          if (o == i || !live[o]) continue;
          const Sphere& b = spheres[o];
          const double e2 = (y - b.centre_m.y) * (y - b.centre_m.y) + (z - b.centre_m.z) * (z - b.centre_m.z);
          if (e2 >= b.radius_m * b.radius_m) continue;
          const double h = std::sqrt(b.radius_m * b.radius_m - e2);
          others.push_back({b.centre_m.x - h, b.centre_m.x + h});
        }
        own += 2.0 * half;
        shared += union_overlap(others, a.centre_m.x - half, a.centre_m.x + half);
      }
    }
    return own > 0.0 ? shared / own : 0.0;
  }

  // Length of [x0, x1] covered by the union of (unsorted) intervals.
  static double union_overlap(std::vector<Interval>& intervals, double x0, double x1) {
    std::sort(intervals.begin(), intervals.end(), [](const Interval& p, const Interval& q) { return p.x0_m < q.x0_m; });
    double total = 0.0, reach = x0;
    for (const Interval& in : intervals) {
      const double lo = std::max(in.x0_m, reach), hi = std::min(in.x1_m, x1);
      if (hi > lo) {
        total += hi - lo;
        reach = hi;
      }
    }
    return total;
  }

  // More samples (check points the spheres left out): the neighbour graph is rebuilt.
  void add_points(const std::vector<glm::dvec3>& points) {
    points_.insert(points_.end(), points.begin(), points.end());
    build_neighbours();
  }

  const std::vector<glm::dvec3>& points() const { return points_; }
  const std::vector<std::vector<int>>& neighbours() const { return neighbours_; }
  size_t interior_count() const { return interior_count_; }
  double step_m() const { return step_m_; }
  double row_step_m() const { return row_step_m_; }
  const InsideRows& rows() const { return rows_; }
  const Axis& row_x() const { return row_x_; }
  const Bounds& bounds() const { return bounds_; }

 private:
  // Each point's ~10 nearest points within reach (a bucket grid of the grid
  // step), made symmetric: the graph the flood fill grows clusters over.
  void build_neighbours() {
    const double cell = step_m_;
    const glm::dvec3 lo = bounds_.min_m - glm::dvec3(cell);
    const glm::ivec3 n = glm::ivec3(glm::ceil((bounds_.max_m - lo) / cell)) + 2;
    auto bucket_of = [&](const glm::dvec3& p) {
      return glm::clamp(glm::ivec3(glm::floor((p - lo) / cell)), glm::ivec3(0), n - 1);
    };
    std::vector<std::vector<int>> buckets(static_cast<size_t>(n.x) * n.y * n.z);
    auto index = [&](const glm::ivec3& b) { return static_cast<size_t>(b.x) + static_cast<size_t>(n.x) * (b.y + static_cast<size_t>(n.y) * b.z); };
    for (size_t i = 0; i < points_.size(); ++i) buckets[index(bucket_of(points_[i]))].push_back(static_cast<int>(i));
    constexpr size_t kNearest = 10;
    std::vector<std::set<int>> graph(points_.size());
    std::vector<std::pair<double, int>> candidates;
    for (size_t i = 0; i < points_.size(); ++i) {
      const glm::ivec3 b = bucket_of(points_[i]);
      for (int reach = 1; reach <= 3; ++reach) {
        candidates.clear();
        for (int dz = -reach; dz <= reach; ++dz)
          for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx) {
              const glm::ivec3 c = b + glm::ivec3(dx, dy, dz);
              if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, n))) continue;
              for (int o : buckets[index(c)])
                if (o != static_cast<int>(i)) {
                  const glm::dvec3 d = points_[static_cast<size_t>(o)] - points_[i];
                  candidates.emplace_back(glm::dot(d, d), o);
                }
            }
        if (candidates.size() >= kNearest) break;
      }
      const size_t keep = std::min(kNearest, candidates.size());
      std::partial_sort(candidates.begin(), candidates.begin() + static_cast<long>(keep), candidates.end());
      for (size_t c = 0; c < keep; ++c) {
        graph[i].insert(candidates[c].second);
        graph[static_cast<size_t>(candidates[c].second)].insert(static_cast<int>(i));
      }
    }
    neighbours_.resize(points_.size());
    for (size_t i = 0; i < points_.size(); ++i) neighbours_[i].assign(graph[i].begin(), graph[i].end());
  }

  FitOptions options_;
  Bounds bounds_;
  double step_m_ = 1.0, row_step_m_ = 0.5;
  Axis row_x_;
  InsideRows rows_;
  std::vector<glm::dvec3> points_;
  size_t interior_count_ = 0;
  std::vector<std::vector<int>> neighbours_;
};

struct State {
  std::vector<Sphere> spheres;
  std::vector<std::vector<int>> clusters;  // point indices; empty: a dead sphere
  std::vector<double> outside_m3;          // V(S_i \ O)
  double energy_m3 = 0.0;
  size_t live() const {
    size_t n = 0;
    for (const auto& c : clusters) n += !c.empty();
    return n;
  }
};

bool covered_by(const std::vector<Sphere>& spheres, const glm::dvec3& q) {
  for (const Sphere& s : spheres)
    if (glm::dot(q - s.centre_m, q - s.centre_m) <= s.radius_m * s.radius_m) return true;
  return false;
}

std::vector<Sphere> live_spheres(const State& s) {
  std::vector<Sphere> out;
  for (size_t i = 0; i < s.spheres.size(); ++i)
    if (!s.clusters[i].empty()) out.push_back(s.spheres[i]);
  return out;
}

class Fitter {
 public:
  // Keeps references to the problem (whose samples it adds to) and the check points.
  Fitter(Problem& problem, const std::vector<glm::dvec3>& check, const FitOptions& options)
      : p_(problem), check_(check), options_(options) {}

  // The check points the spheres leave out join the samples, and one round
  // takes them in. Returns how many there were.
  size_t absorb_missed(State& s) {
    const std::vector<Sphere> live = live_spheres(s);
    std::vector<glm::dvec3> missed;
    for (const glm::dvec3& q : check_)
      if (!covered_by(live, q)) missed.push_back(q);
    if (missed.empty()) return 0;
    p_.add_points(missed);
    round(s);
    say(std::to_string(missed.size()) + " of " + std::to_string(check_.size()) +
        " check points outside the spheres joined the samples" +
        format(": outside volume (sum over spheres) %.4g m^3", s.energy_m3));
    return missed.size();
  }

  void say(const std::string& line) const {
    if (options_.progress) options_.progress(line);
  }

  double radius_for(const std::vector<int>& cluster, const glm::dvec3& c) const {
    double r2 = 0.0;
    for (int i : cluster) {
      const glm::dvec3 d = p_.points()[static_cast<size_t>(i)] - c;
      r2 = std::max(r2, glm::dot(d, d));
    }
    return std::sqrt(r2);
  }

  glm::dvec3 box_centre(const std::vector<int>& cluster) const {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (int i : cluster) {
      lo = glm::min(lo, p_.points()[static_cast<size_t>(i)]);
      hi = glm::max(hi, p_.points()[static_cast<size_t>(i)]);
    }
    return 0.5 * (lo + hi);
  }

  // The centre that minimises the outside volume of the smallest sphere about
  // it holding the cluster: a compass search from the better of `start` and
  // the cluster's box centre.
  Sphere optimise(const std::vector<int>& cluster, const glm::dvec3& start, double* outside_m3) const {
    auto cost = [&](const glm::dvec3& c) { return p_.outside_volume_m3(c, radius_for(cluster, c)); };
    glm::dvec3 c = start;
    double f = cost(c);
    const glm::dvec3 b = box_centre(cluster);
    const double fb = cost(b);
    if (fb < f) {
      c = b;
      f = fb;
    }
    double step = std::max(p_.step_m(), 0.1 * radius_for(cluster, c));
    const double min_step = p_.step_m() / 16.0;
    static const glm::dvec3 kDirections[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int evals = 0; step > min_step && evals < 240;) {
      glm::dvec3 best_c = c;
      double best_f = f;
      for (const glm::dvec3& d : kDirections) {
        const glm::dvec3 t = c + step * d;
        const double ft = cost(t);
        ++evals;
        if (ft < best_f) {
          best_f = ft;
          best_c = t;
        }
      }
      if (best_f < f) {
        c = best_c;
        f = best_f;
      } else {
        step *= 0.5;
      }
    }
    if (outside_m3) *outside_m3 = f;
    return {c, radius_for(cluster, c)};
  }

  // Flood-fill assignment (see sphere_fit.h). Returns the clusters.
  std::vector<std::vector<int>> assign(const State& s) const {
    const auto& pts = p_.points();
    const size_t n = pts.size(), k = s.spheres.size();
    auto key = [&](size_t sphere, size_t q) {
      return glm::length(pts[q] - s.spheres[sphere].centre_m) - s.spheres[sphere].radius_m;
    };
    std::vector<int> owner(n, -1);
    using Entry = std::tuple<double, int, int>;  // key, sphere, point
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    // Seeds: each live sphere's deepest point, deepest spheres first; a point is one sphere's seed.
    std::vector<std::pair<double, int>> order;
    std::vector<int> best(k, -1);
    for (size_t i = 0; i < k; ++i) {
      if (s.clusters[i].empty()) continue;
      double best_key = std::numeric_limits<double>::max();
      for (size_t q = 0; q < n; ++q) {
        const double kq = key(i, q);
        if (kq < best_key) {
          best_key = kq;
          best[i] = static_cast<int>(q);
        }
      }
      order.emplace_back(best_key, static_cast<int>(i));
    }
    std::sort(order.begin(), order.end());
    std::vector<bool> seeded(n, false);
    for (const auto& [best_key, i] : order) {
      int seed = best[static_cast<size_t>(i)];
      if (seeded[static_cast<size_t>(seed)]) {
        double bk = std::numeric_limits<double>::max();
        for (size_t q = 0; q < n; ++q)
          if (!seeded[q] && key(static_cast<size_t>(i), q) < bk) {
            bk = key(static_cast<size_t>(i), q);
            seed = static_cast<int>(q);
          }
        if (seeded[static_cast<size_t>(seed)]) continue;  // more spheres than points
      }
      seeded[static_cast<size_t>(seed)] = true;
      queue.emplace(key(static_cast<size_t>(i), static_cast<size_t>(seed)), i, seed);
    }
    while (!queue.empty()) {
      const auto [kq, i, q] = queue.top();
      queue.pop();
      if (owner[static_cast<size_t>(q)] >= 0) continue;
      owner[static_cast<size_t>(q)] = i;
      for (int m : p_.neighbours()[static_cast<size_t>(q)])
        if (owner[static_cast<size_t>(m)] < 0) queue.emplace(key(static_cast<size_t>(i), static_cast<size_t>(m)), i, m);
    }
    // Points the graph does not connect to any seed: the sphere nearest to holding them.
    for (size_t q = 0; q < n; ++q) {
      if (owner[q] >= 0) continue;
      double bk = std::numeric_limits<double>::max();
      for (size_t i = 0; i < k; ++i)
        if (!s.clusters[i].empty() && key(i, q) < bk) {
          bk = key(i, q);
          owner[q] = static_cast<int>(i);
        }
    }
    std::vector<std::vector<int>> clusters(k);
    for (size_t q = 0; q < n; ++q)
      if (owner[q] >= 0) clusters[static_cast<size_t>(owner[q])].push_back(static_cast<int>(q));
    return clusters;
  }

  void update_energy(State& s) const {
    s.energy_m3 = 0.0;
    for (size_t i = 0; i < s.spheres.size(); ++i)
      if (!s.clusters[i].empty()) s.energy_m3 += s.outside_m3[i];
  }

  // Splits sphere `from`'s cluster in two along its principal axis (2-means);
  // `from` keeps one half, sphere `into` (a dead slot or a new one) the other.
  bool split(State& s, size_t from, size_t into) const {
    const std::vector<int> cluster = s.clusters[from];
    if (cluster.size() < 2) return false;
    const auto& pts = p_.points();
    glm::dvec3 mean(0.0);
    for (int i : cluster) mean += pts[static_cast<size_t>(i)];
    mean /= static_cast<double>(cluster.size());
    glm::dmat3 cov(0.0);
    for (int i : cluster) {
      const glm::dvec3 d = pts[static_cast<size_t>(i)] - mean;
      cov += glm::outerProduct(d, d);
    }
    glm::dvec3 axis = glm::normalize(glm::dvec3(1.0, 0.7, 0.3));
    for (int it = 0; it < 32; ++it) {
      const glm::dvec3 next = cov * axis;
      if (glm::length(next) == 0.0) break;
      axis = glm::normalize(next);
    }
    int lo = cluster[0], hi = cluster[0];
    for (int i : cluster) {
      if (glm::dot(pts[static_cast<size_t>(i)] - mean, axis) < glm::dot(pts[static_cast<size_t>(lo)] - mean, axis)) lo = i;
      if (glm::dot(pts[static_cast<size_t>(i)] - mean, axis) > glm::dot(pts[static_cast<size_t>(hi)] - mean, axis)) hi = i;
    }
    glm::dvec3 ca = pts[static_cast<size_t>(lo)], cb = pts[static_cast<size_t>(hi)];
    if (ca == cb) return false;
    std::vector<int> a, b;
    for (int it = 0; it < 8; ++it) {
      a.clear();
      b.clear();
      for (int i : cluster) {
        const glm::dvec3& q = pts[static_cast<size_t>(i)];
        (glm::dot(q - ca, q - ca) <= glm::dot(q - cb, q - cb) ? a : b).push_back(i);
      }
      if (a.empty() || b.empty()) return false;
      glm::dvec3 ma(0.0), mb(0.0);
      for (int i : a) ma += pts[static_cast<size_t>(i)];
      for (int i : b) mb += pts[static_cast<size_t>(i)];
      ca = ma / static_cast<double>(a.size());
      cb = mb / static_cast<double>(b.size());
    }
    if (into >= s.spheres.size()) {
      s.spheres.resize(into + 1);
      s.clusters.resize(into + 1);
      s.outside_m3.resize(into + 1, 0.0);
    }
    s.clusters[from] = a;
    s.clusters[into] = b;
    s.spheres[from] = optimise(a, box_centre(a), &s.outside_m3[from]);
    s.spheres[into] = optimise(b, box_centre(b), &s.outside_m3[into]);
    return true;
  }

  // The live sphere of largest outside volume that can be split (not `except`).
  int worst(const State& s, size_t except = static_cast<size_t>(-1)) const {
    int w = -1;
    for (size_t i = 0; i < s.spheres.size(); ++i)
      if (i != except && s.clusters[i].size() >= 2 && (w < 0 || s.outside_m3[i] > s.outside_m3[static_cast<size_t>(w)]))
        w = static_cast<int>(i);
    return w;
  }

  // One round: assignment, then each changed cluster's centre; dead spheres
  // come back by splitting the worst.
  void round(State& s) const {
    std::vector<std::vector<int>> clusters = assign(s);
    for (size_t i = 0; i < s.spheres.size(); ++i) {
      if (clusters[i] == s.clusters[i]) continue;
      s.clusters[i] = std::move(clusters[i]);
      if (!s.clusters[i].empty()) s.spheres[i] = optimise(s.clusters[i], s.spheres[i].centre_m, &s.outside_m3[i]);
    }
    for (size_t i = 0; i < s.spheres.size(); ++i) {
      if (!s.clusters[i].empty()) continue;
      const int w = worst(s);
      if (w < 0 || !split(s, static_cast<size_t>(w), i)) break;
    }
    update_energy(s);
  }

  State run() {
    const auto& pts = p_.points();
    State s;
    std::vector<int> all(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) all[i] = static_cast<int>(i);
    s.clusters.push_back(all);
    s.outside_m3.push_back(0.0);
    s.spheres.push_back(optimise(all, box_centre(all), &s.outside_m3[0]));
    update_energy(s);
    const size_t target = std::min(static_cast<size_t>(options_.spheres), pts.size());
    while (s.spheres.size() < target) {
      const int w = worst(s);
      if (w < 0 || !split(s, static_cast<size_t>(w), s.spheres.size())) break;
      round(s);
      if (s.spheres.size() % 4 == 0 || s.spheres.size() == target)
        say("split to " + std::to_string(s.spheres.size()) + " spheres: outside volume (sum over spheres) " +
            format("%.4g m^3", s.energy_m3));
    }

    // Check points left out join the samples now and every 10 iterations, so
    // the iterations optimise with them (E changes with the samples: best restarts).
    absorb_missed(s);
    State best = s;
    std::set<size_t> tried;  // spheres whose deletion failed since the last kept teleport
    for (int it = 1; it <= options_.iterations; ++it) {
      if (it % 10 == 0 && absorb_missed(s) > 0) {
        best = s;
        tried.clear();
      }
      round(s);
      if (s.energy_m3 < best.energy_m3) best = s;
      std::string teleport = "no teleport";
      if (s.live() >= 3) {
        std::vector<bool> live(s.spheres.size());
        for (size_t i = 0; i < live.size(); ++i) live[i] = !s.clusters[i].empty();
        int remove = -1;
        double most = -1.0;
        for (size_t i = 0; i < s.spheres.size(); ++i) {
          if (!live[i] || tried.count(i)) continue;
          const double f = p_.overlap_fraction(s.spheres, live, i);
          if (f > most) {
            most = f;
            remove = static_cast<int>(i);
          }
        }
        const int w = remove >= 0 ? worst(s, static_cast<size_t>(remove)) : -1;
        if (remove >= 0 && w >= 0) {
          State trial = s;
          trial.clusters[static_cast<size_t>(remove)].clear();
          if (split(trial, static_cast<size_t>(w), static_cast<size_t>(remove))) {
            round(trial);
            round(trial);
            const bool kept = trial.energy_m3 < s.energy_m3;
            teleport = format("teleport (delete %.0f, %.0f %% overlapped; split %.0f): ", remove, 100.0 * most, w) +
                       (kept ? "kept" : "undone");
            if (kept) {
              s = std::move(trial);
              tried.clear();
              if (s.energy_m3 < best.energy_m3) best = s;
            } else {
              tried.insert(static_cast<size_t>(remove));
            }
          }
        }
      }
      say("iteration " + std::to_string(it) + "/" + std::to_string(options_.iterations) +
          format(": outside volume (sum over spheres) %.4g m^3, ", s.energy_m3) + teleport);
    }
    return best;
  }

 private:
  Problem& p_;
  const std::vector<glm::dvec3>& check_;
  FitOptions options_;
};

// Grows spheres to take in every check point left out, each by the sphere
// that has to grow least. Returns how many points were left out.
size_t cover(std::vector<Sphere>& spheres, const std::vector<glm::dvec3>& points) {
  size_t missed = 0;
  for (const glm::dvec3& q : points) {
    bool covered = false;
    size_t nearest = 0;
    double gap = std::numeric_limits<double>::max();
    for (size_t i = 0; i < spheres.size() && !covered; ++i) {
      const double d = glm::length(q - spheres[i].centre_m);
      covered = d <= spheres[i].radius_m;
      if (d - spheres[i].radius_m < gap) {
        gap = d - spheres[i].radius_m;
        nearest = i;
      }
    }
    if (covered) continue;
    ++missed;
    spheres[nearest].radius_m = glm::length(q - spheres[nearest].centre_m);
  }
  return missed;
}

}  // namespace

std::vector<Sphere> fit_spheres(const TriangleMesh& mesh, const FitOptions& options) {
  if (options.spheres < 1 || options.spheres > 1024)
    throw std::invalid_argument("spheres must be in [1, 1024], got " + std::to_string(options.spheres));
  if (options.grid < 4 || options.grid > 1024)
    throw std::invalid_argument("grid must be in [4, 1024], got " + std::to_string(options.grid));
  if (options.surface_points < 0 || options.iterations < 0)
    throw std::invalid_argument("surface_points and iterations must be >= 0");
  if (mesh.triangles.empty() || !(mesh_bounds(mesh).longest_side_m() > 0.0))
    throw std::runtime_error("the mesh is empty");

  Problem problem(mesh, options);
  if (options.progress)
    options.progress("samples: " + std::to_string(problem.interior_count()) + " inside points (grid step " +
                     format("%.3g m), ", problem.step_m()) + std::to_string(options.surface_points) +
                     " surface points, " + std::to_string(mesh.vertices.size()) + " vertices");
  // Coverage between the samples: a denser set of check points. The ones the
  // spheres leave out join the samples (after the splits, every 10 iterations
  // and up to 3 times at the end), so the spheres take them in where it costs
  // least; what is still left out is taken in by growing the nearest sphere.
  std::vector<glm::dvec3> check = sample_edges(mesh, 0.25 * problem.step_m());
  const std::vector<glm::dvec3> surface = sample_surface(mesh, 4 * options.surface_points, options.seed ^ 0x6A09E667F3BCC909ull);
  check.insert(check.end(), surface.begin(), surface.end());
  Problem::append_inside_points(problem.rows(), problem.row_x(), problem.row_step_m(), check);

  Fitter fitter(problem, check, options);
  State best = fitter.run();
  for (int pass = 1; pass <= 3; ++pass) {
    State s = best;
    if (fitter.absorb_missed(s) == 0) break;
    best = s;
    for (int r = 0; r < 3; ++r) {
      fitter.round(s);
      if (s.energy_m3 < best.energy_m3) best = s;
    }
  }
  std::vector<Sphere> spheres = live_spheres(best);
  std::vector<double> before(spheres.size());
  for (size_t i = 0; i < spheres.size(); ++i) before[i] = spheres[i].radius_m;
  const size_t missed = cover(spheres, check);
  double grown = 0.0;
  for (size_t i = 0; i < spheres.size(); ++i) grown = std::max(grown, spheres[i].radius_m - before[i]);
  // A hair more, so rounding never leaves a sampled point just outside.
  const double margin = 1e-9 * problem.bounds().longest_side_m();
  for (Sphere& s : spheres) s.radius_m += margin;
  if (options.progress)
    options.progress("coverage: " + std::to_string(check.size()) + " check points, " + std::to_string(missed) +
                     format(" outside the spheres; the largest growth %.3g m", grown));
  return spheres;
}

// ------------------------------------------------------------------ measure

namespace {

// Sorted, disjoint union of intervals.
std::vector<Interval> merged(std::vector<Interval> v) {
  std::sort(v.begin(), v.end(), [](const Interval& a, const Interval& b) { return a.x0_m < b.x0_m; });
  std::vector<Interval> out;
  for (const Interval& i : v) {
    if (!out.empty() && i.x0_m <= out.back().x1_m) out.back().x1_m = std::max(out.back().x1_m, i.x1_m);
    else out.push_back(i);
  }
  return out;
}

double total_length(const std::vector<Interval>& v) {
  double t = 0.0;
  for (const Interval& i : v) t += i.x1_m - i.x0_m;
  return t;
}

// Length of the intersection of two sorted, disjoint interval lists.
double common_length(const std::vector<Interval>& a, const std::vector<Interval>& b) {
  double t = 0.0;
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double lo = std::max(a[i].x0_m, b[j].x0_m), hi = std::min(a[i].x1_m, b[j].x1_m);
    if (hi > lo) t += hi - lo;
    if (a[i].x1_m < b[j].x1_m) ++i;
    else ++j;
  }
  return t;
}

// Distance from points to the surface of a union of spheres (exact; see sphere_fit.h).
class UnionSurface {
 public:
  UnionSurface(const std::vector<Sphere>& spheres, double scale_m) : s_(spheres), tol_(1e-9 * scale_m) {
    const size_t n = s_.size();
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j) {
        const glm::dvec3 d = s_[j].centre_m - s_[i].centre_m;
        const double dist = glm::length(d);
        const double ri = s_[i].radius_m, rj = s_[j].radius_m;
        if (dist >= ri + rj || dist <= std::fabs(ri - rj) || dist == 0.0) continue;
        Circle c;
        c.axis = d / dist;
        const double a = (dist * dist + ri * ri - rj * rj) / (2.0 * dist);
        c.centre = s_[i].centre_m + a * c.axis;
        c.radius = std::sqrt(std::max(0.0, ri * ri - a * a));
        c.i = i;
        c.j = j;
        circles_.push_back(c);
      }
    for (size_t a = 0; a < circles_.size(); ++a)
      for (size_t k = circles_[a].j + 1; k < n; ++k) triple_points(circles_[a].i, circles_[a].j, k);
  }

  double distance(const glm::dvec3& p) const {
    double best = std::numeric_limits<double>::max();
    const size_t none = static_cast<size_t>(-1);
    for (size_t i = 0; i < s_.size(); ++i) {
      const glm::dvec3 d = p - s_[i].centre_m;
      const double len = glm::length(d);
      if (len == 0.0) continue;
      const double candidate = std::fabs(len - s_[i].radius_m);
      if (candidate >= best) continue;
      if (!covered(s_[i].centre_m + (s_[i].radius_m / len) * d, i, none)) best = candidate;
    }
    for (const Circle& c : circles_) {
      glm::dvec3 v = p - c.centre;
      v -= glm::dot(v, c.axis) * c.axis;
      if (glm::length(v) == 0.0) {  // on the circle's axis: every point of it is nearest
        v = glm::cross(c.axis, std::fabs(c.axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0));
      }
      const glm::dvec3 q = c.centre + (c.radius / glm::length(v)) * v;
      const double candidate = glm::length(p - q);
      if (candidate < best && !covered(q, c.i, c.j)) best = candidate;
    }
    for (const glm::dvec3& v : vertices_) best = std::min(best, glm::length(p - v));
    if (best == std::numeric_limits<double>::max()) {  // degenerate: fall back to the nearest sphere
      for (const Sphere& s : s_) best = std::min(best, std::fabs(glm::length(p - s.centre_m) - s.radius_m));
    }
    return best;
  }

 private:
  struct Circle {
    glm::dvec3 centre, axis;
    double radius;
    size_t i, j;
  };

  bool covered(const glm::dvec3& q, size_t a, size_t b, size_t c = static_cast<size_t>(-1)) const {
    for (size_t k = 0; k < s_.size(); ++k) {
      if (k == a || k == b || k == c) continue;
      const double r = s_[k].radius_m - tol_;
      if (r > 0.0 && glm::dot(q - s_[k].centre_m, q - s_[k].centre_m) < r * r) return true;
    }
    return false;
  }

  // The points where spheres i, j, k meet that no other sphere covers.
  void triple_points(size_t i, size_t j, size_t k) {
    const glm::dvec3 p1 = s_[i].centre_m, p2 = s_[j].centre_m, p3 = s_[k].centre_m;
    const double r1 = s_[i].radius_m, r2 = s_[j].radius_m, r3 = s_[k].radius_m;
    const double d = glm::length(p2 - p1);
    if (d == 0.0) return;
    const glm::dvec3 ex = (p2 - p1) / d;
    const double a = glm::dot(ex, p3 - p1);
    glm::dvec3 ey = p3 - p1 - a * ex;
    const double b = glm::length(ey);
    if (b < 1e-12 * (d + glm::length(p3 - p1))) return;  // centres in a line
    ey /= b;
    const glm::dvec3 ez = glm::cross(ex, ey);
    const double x = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    const double y = (r1 * r1 - r3 * r3 + a * a + b * b) / (2.0 * b) - (a / b) * x;
    const double z2 = r1 * r1 - x * x - y * y;
    if (z2 < 0.0) return;
    const double z = std::sqrt(z2);
    for (double sign : {1.0, -1.0}) {
      const glm::dvec3 q = p1 + x * ex + y * ey + sign * z * ez;
      if (!covered(q, i, j, k)) vertices_.push_back(q);
      if (z == 0.0) break;
    }
  }

  const std::vector<Sphere>& s_;
  double tol_;
  std::vector<Circle> circles_;
  std::vector<glm::dvec3> vertices_;
};

}  // namespace

double union_surface_distance_m(const std::vector<Sphere>& spheres, const glm::dvec3& p_m) {
  double scale = 0.0;
  for (const Sphere& s : spheres) scale = std::max(scale, glm::length(s.centre_m) + s.radius_m);
  return spheres.empty() ? 0.0 : UnionSurface(spheres, scale).distance(p_m);
}

FitError measure_fit(const TriangleMesh& mesh, const std::vector<Sphere>& spheres, int grid_samples) {
  if (grid_samples < 1) throw std::invalid_argument("grid_samples must be >= 1");
  FitError e;
  const Bounds mb = mesh_bounds(mesh);
  const double scale = mb.longest_side_m();
  if (!(scale > 0.0)) return e;
  const double step = scale / grid_samples;
  glm::dvec3 lo = mb.min_m, hi = mb.max_m;
  for (const Sphere& s : spheres) {
    lo = glm::min(lo, s.centre_m - glm::dvec3(s.radius_m));
    hi = glm::max(hi, s.centre_m + glm::dvec3(s.radius_m));
  }
  // A lattice through the mesh's centre, reaching out over the spheres: the
  // mesh is sampled on the same rows whatever the spheres.
  auto axis_through = [&](double centre, double l, double h) {
    Axis a;
    a.origin = centre - std::ceil((centre - l) / step) * step;
    a.n = static_cast<int>(std::floor((h - a.origin) / step)) + 1;
    return a;
  };
  const glm::dvec3 mc = 0.5 * (mb.min_m + mb.max_m);
  const Axis ay = axis_through(mc.y, lo.y, hi.y), az = axis_through(mc.z, lo.z, hi.z);
  const InsideRows rows = inside_rows(mesh, ay.origin, az.origin, step, ay.n, az.n);
  double mesh_len = 0.0, outside_len = 0.0, uncovered_len = 0.0;
  std::vector<Interval> chords;
  for (int k = 0; k < rows.nz; ++k) {
    const double z = rows.z0_m + k * step;
    for (int j = 0; j < rows.ny; ++j) {
      const double y = rows.y0_m + j * step;
      chords.clear();
      for (const Sphere& s : spheres) {
        const double d2 = (y - s.centre_m.y) * (y - s.centre_m.y) + (z - s.centre_m.z) * (z - s.centre_m.z);
        if (d2 >= s.radius_m * s.radius_m) continue;
        const double half = std::sqrt(s.radius_m * s.radius_m - d2);
        chords.push_back({s.centre_m.x - half, s.centre_m.x + half});
      }
      const std::vector<Interval> in_spheres = merged(chords);
      const std::vector<Interval>& in_mesh = *rows.row(j, k);
      const double both = common_length(in_mesh, in_spheres);
      const double m = total_length(in_mesh), s = total_length(in_spheres);
      mesh_len += m;
      outside_len += s - both;
      uncovered_len += m - both;
    }
  }
  const double area = step * step;
  e.mesh_volume_m3 = mesh_len * area;
  e.outside_volume_m3 = outside_len * area;
  e.uncovered_volume_m3 = uncovered_len * area;

  const UnionSurface surface(spheres, scale);
  const std::vector<glm::dvec3> samples = sample_surface(mesh, 8192, 0x5EEDull);
  double sum = 0.0;
  for (const glm::dvec3& p : samples) {
    const double d = spheres.empty() ? 0.0 : surface.distance(p);
    sum += d;
    e.surface_distance_max_m = std::max(e.surface_distance_max_m, d);
  }
  e.surface_distance_mean_m = samples.empty() ? 0.0 : sum / static_cast<double>(samples.size());
  return e;
}

}  // namespace atmo::spheres
