// Reference-line and lane-centre evaluation [Forklift thesis, section 5.1, eq. 5.1-5.4], generalised
// to every OpenDRIVE plan-view geometry.

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include "map/opendrive.hpp"

namespace fleet::map {

namespace {

constexpr double kPi = std::numbers::pi;

// 10-point Gauss-Legendre nodes and weights on [-1, 1] (symmetric half).
constexpr std::array<double, 5> kGlNodes = {0.1488743389816312, 0.4333953941292472, 0.6794095682990244,
                                            0.8650633666889845, 0.9739065285171717};
constexpr std::array<double, 5> kGlWeights = {0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
                                              0.1494513491505806, 0.0666713443086881};

/// Integral of f over [a, b] by composite 10-point Gauss-Legendre on `panels` panels.
template <typename F>
auto gauss_legendre(F&& f, double a, double b, int panels) {
  using R = decltype(f(a));
  R total{};
  const double h = (b - a) / panels;
  for (int k = 0; k < panels; ++k) {
    const double mid = a + (k + 0.5) * h;
    const double half = 0.5 * h;
    R sum{};
    for (std::size_t i = 0; i < kGlNodes.size(); ++i) {
      sum += kGlWeights[i] * (f(mid - half * kGlNodes[i]) + f(mid + half * kGlNodes[i]));
    }
    total += half * sum;
  }
  return total;
}

RefPoint to_global(const Geometry& g, double u, double v, double local_hdg) {
  const double c = std::cos(g.hdg);
  const double s = std::sin(g.hdg);
  // [Forklift thesis, eq. 5.3-5.4]
  return {g.x + u * c - v * s, g.y + u * s + v * c, g.hdg + local_hdg};
}

RefPoint arc(const Geometry& g, double k, double ds) {
  if (std::abs(k) * ds < 1e-9) {
    // Below this turn the chord formula loses more to cancellation than the straight line does.
    const double h = g.hdg + 0.5 * k * ds;
    return {g.x + ds * std::cos(h), g.y + ds * std::sin(h), g.hdg + k * ds};
  }
  const double h1 = g.hdg + k * ds;
  return {g.x + (std::sin(h1) - std::sin(g.hdg)) / k, g.y - (std::cos(h1) - std::cos(g.hdg)) / k, h1};
}

/// Clothoid by quadrature; used where the Fresnel form is ill-conditioned (curvature almost
/// constant along a long spiral, so the shifted Fresnel arguments become huge).
RefPoint spiral_quadrature(const Geometry& g, double k0, double rate, double ds) {
  const auto heading = [&](double u) { return g.hdg + k0 * u + 0.5 * rate * u * u; };
  const double turn = std::max(std::abs(k0), std::abs(k0 + rate * ds)) * ds;
  // A panel per quarter radian of turn. The cap keeps absurd inputs (a fuzzed file) at bounded
  // cost: 1000 panels hold 250 rad, forty full circles, more than any road turns; beyond that
  // the result loses accuracy instead of taking minutes a point.
  const double wanted = 1.0 + turn / 0.25 + std::min(ds, 5000.0) / 50.0;
  const int panels = std::isfinite(wanted) ? static_cast<int>(std::min(wanted, 1000.0)) : 1;
  const std::complex<double> z = gauss_legendre([&](double u) { return std::polar(1.0, heading(u)); }, 0.0, ds, panels);
  return {g.x + z.real(), g.y + z.imag(), heading(ds)};
}

RefPoint spiral(const Geometry& g, double ds) {
  const double k0 = g.curv_start;
  const double rate = g.length > 0.0 ? (g.curv_end - g.curv_start) / g.length : 0.0;
  if (rate == 0.0) return arc(g, k0, ds);
  if (k0 * k0 / std::abs(rate) > 1e6) return spiral_quadrature(g, k0, rate, ds);
  // Heading hdg + k0 u + rate u^2 / 2 = (rate / 2) t^2 + phi with t = u + k0 / rate. With
  // t = a tau, a = sqrt(pi / |rate|), the integral of exp(i heading) is
  // a exp(i phi) [C(tau) + i sign S(tau)] between the two tau (Fresnel integrals).
  const double sign = rate > 0.0 ? 1.0 : -1.0;
  const double a = std::sqrt(kPi / std::abs(rate));
  const double phi = g.hdg - k0 * k0 / (2.0 * rate);
  const double tau0 = (k0 / rate) / a;
  const double tau1 = (ds + k0 / rate) / a;
  double c0 = 0.0, s0 = 0.0, c1 = 0.0, s1 = 0.0;
  fresnel(tau0, c0, s0);
  fresnel(tau1, c1, s1);
  const std::complex<double> z = a * std::polar(1.0, phi) * std::complex<double>(c1 - c0, sign * (s1 - s0));
  return {g.x + z.real(), g.y + z.imag(), g.hdg + k0 * ds + 0.5 * rate * ds * ds};
}

RefPoint poly3(const Geometry& g, double ds) {
  // v(u) is given over the local u axis but s runs along the curve, so u is found by inverting
  // the arc length L(u) = int_0^u sqrt(1 + v'(x)^2) dx with Newton steps.
  const auto dv = [&](double u) { return g.b + u * (2.0 * g.c + 3.0 * g.d * u); };
  const auto speed = [&](double u) { return std::sqrt(1.0 + dv(u) * dv(u)); };
  const auto arc_length = [&](double u) {
    const double wanted = 1.0 + std::abs(u) / 5.0;
    return u == 0.0
               ? 0.0
               : gauss_legendre(speed, 0.0, u, std::isfinite(wanted) ? static_cast<int>(std::min(wanted, 1e4)) : 1);
  };
  double u = ds / speed(0.0);
  for (int i = 0; i < 30; ++i) {
    const double step = (arc_length(u) - ds) / speed(u);
    u -= step;
    if (std::abs(step) < 1e-12) break;
  }
  const double v = g.a + u * (g.b + u * (g.c + u * g.d));
  return to_global(g, u, v, std::atan(dv(u)));
}

/// The end of a paramPoly3's p range: [0, 1] (normalized) or [0, length] (arcLength).
double p_range_end(const Geometry& g) {
  return g.normalized ? 1.0 : g.length;
}

/// |(u'(p), v'(p))|, the speed of a paramPoly3's cubic.
double param_poly3_speed(const Geometry& g, double p) {
  return std::hypot(g.bu + p * (2.0 * g.cu + 3.0 * g.du * p), g.bv + p * (2.0 * g.cv + 3.0 * g.dv * p));
}

/// Arc length of a paramPoly3's cubic from p = 0 to `p`, about one Gauss-Legendre panel per 5 m
/// of curve, as for poly3.
double param_poly3_arc_length(const Geometry& g, double p) {
  if (p == 0.0) return 0.0;
  const double wanted = 1.0 + std::abs(p / p_range_end(g)) * g.length / 5.0;
  return gauss_legendre([&](double q) { return param_poly3_speed(g, q); }, 0.0, p,
                        std::isfinite(wanted) ? static_cast<int>(std::min(wanted, 1e4)) : 1);
}

RefPoint param_poly3(const Geometry& g, double ds) {
  // s runs along the curve by arc length, and the cubic's parameter p does not: its speed
  // |(u'(p), v'(p))| is near 1 at best. p is found by inverting the arc length A(p) with Newton
  // steps, A scaled so that the geometry's declared length lands on the end of the p range (the
  // end point stays where the file puts it, whatever rounding its length carries).
  const double p_end = p_range_end(g);
  const auto speed = [&](double p) { return param_poly3_speed(g, p); };
  double p = 0.0;
  if (g.length > 0.0 && p_end > 0.0) {
    p = ds / g.length * p_end;
    const double total = g.curve_arc_length > 0.0 ? g.curve_arc_length : paramPoly3_arc_length(g);
    if (total > 0.0 && std::isfinite(total)) {
      const double target = ds * total / g.length;
      // One whole integral for the first guess; each Newton step then adds only the integral over
      // the step itself, which one Gauss-Legendre panel gives exactly enough (the steps shrink).
      double at_p = param_poly3_arc_length(g, p);
      for (int i = 0; i < 40; ++i) {
        const double sp = speed(p);
        if (!(sp > 1e-12)) break;  // a cusp: the linear guess is as good as any
        const double step = (at_p - target) / sp;
        at_p += gauss_legendre(speed, p, p - step, 1);
        p -= step;
        if (std::abs(step) < 1e-14 * std::max(1.0, p_end)) break;
      }
    }
  }
  const double u = g.au + p * (g.bu + p * (g.cu + p * g.du));
  const double v = g.av + p * (g.bv + p * (g.cv + p * g.dv));
  double du = g.bu + p * (2.0 * g.cu + 3.0 * g.du * p);
  double dv = g.bv + p * (2.0 * g.cv + 3.0 * g.dv * p);
  if (du == 0.0 && dv == 0.0) {
    // A cusp where the tangent vanishes: the second derivative gives the direction.
    du = 2.0 * g.cu + 6.0 * g.du * p;
    dv = 2.0 * g.cv + 6.0 * g.dv * p;
  }
  return to_global(g, u, v, (du == 0.0 && dv == 0.0) ? 0.0 : std::atan2(dv, du));
}

template <typename T>
const T* record_at(const std::vector<T>& records, double s) {
  if (records.empty()) return nullptr;
  const auto it = std::upper_bound(records.begin(), records.end(), s, [](double v, const T& r) { return v < r.s; });
  return it == records.begin() ? &records.front() : &*(it - 1);
}

}  // namespace

void fresnel(double x, double& c, double& s) {
  // Power series below 1.5, complex continued fraction (modified Lentz) above: both converge to
  // double precision, which the clothoid needs to stay within 1e-6 m over 500 m.
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  constexpr double kTiny = std::numeric_limits<double>::min();
  constexpr int kMaxIter = 200;
  const double ax = std::abs(x);
  if (ax < std::sqrt(kTiny)) {
    c = x;
    s = 0.0;
    return;
  }
  if (ax <= 1.5) {
    double sum = 0.0, sums = 0.0, sumc = ax, sign = 1.0, term = ax;
    const double fact = 0.5 * kPi * ax * ax;
    bool odd = true;
    int n = 3;
    for (int k = 1; k <= kMaxIter; ++k) {
      term *= fact / k;
      sum += sign * term / n;
      const double test = std::abs(sum) * kEps;
      if (odd) {
        sign = -sign;
        sums = sum;
        sum = sumc;
      } else {
        sumc = sum;
        sum = sums;
      }
      if (term < test) break;
      odd = !odd;
      n += 2;
    }
    c = sumc;
    s = sums;
  } else {
    const double pix2 = kPi * ax * ax;
    std::complex<double> b(1.0, -pix2);
    std::complex<double> cc(1.0 / kTiny, 0.0);
    std::complex<double> d = 1.0 / b;
    std::complex<double> h = d;
    int n = -1;
    for (int k = 2; k <= kMaxIter; ++k) {
      n += 2;
      const double an = -static_cast<double>(n) * (n + 1);
      b += 4.0;
      d = 1.0 / (an * d + b);
      cc = b + an / cc;
      const std::complex<double> del = cc * d;
      h *= del;
      if (std::abs(del.real() - 1.0) + std::abs(del.imag()) < kEps) break;
    }
    h *= std::complex<double>(ax, -ax);
    const std::complex<double> cs =
        std::complex<double>(0.5, 0.5) * (1.0 - std::complex<double>(std::cos(0.5 * pix2), std::sin(0.5 * pix2)) * h);
    c = cs.real();
    s = cs.imag();
  }
  if (x < 0.0) {
    c = -c;
    s = -s;
  }
}

double paramPoly3_arc_length(const Geometry& g) {
  return param_poly3_arc_length(g, p_range_end(g));
}

RefPoint evaluate_geometry(const Geometry& g, double ds) {
  ds = std::clamp(ds, 0.0, g.length);
  switch (g.kind) {
    case GeometryKind::kLine:
      return {g.x + ds * std::cos(g.hdg), g.y + ds * std::sin(g.hdg), g.hdg};
    case GeometryKind::kArc:
      return arc(g, g.curvature, ds);
    case GeometryKind::kSpiral:
      return spiral(g, ds);
    case GeometryKind::kPoly3:
      return poly3(g, ds);
    case GeometryKind::kParamPoly3:
      return param_poly3(g, ds);
  }
  return {g.x, g.y, g.hdg};
}

RefPoint evaluate_reference(const Road& road, double s) {
  s = std::clamp(s, 0.0, road.length);
  const Geometry* g = record_at(road.plan_view, s);
  return evaluate_geometry(*g, s - g->s);
}

double lane_offset_at(const Road& road, double s) {
  const CubicPoly* o = record_at(road.lane_offsets, s);
  return (o == nullptr || s < o->s) ? 0.0 : o->at(s - o->s);
}

std::size_t section_index_at(const Road& road, double s) {
  const LaneSection* sec = record_at(road.sections, s);
  return static_cast<std::size_t>(sec - road.sections.data());
}

double lane_width_at(const Road& road, std::size_t section, int lane_id, double s) {
  const LaneSection& sec = road.sections.at(section);
  const Lane* lane = sec.find(lane_id);
  if (lane == nullptr) return 0.0;
  const double ds = std::max(0.0, s - sec.s);
  const CubicPoly* w = record_at(lane->widths, ds);
  return w == nullptr ? 0.0 : w->at(ds - w->s);
}

double lane_center_t(const Road& road, std::size_t section, int lane_id, double s) {
  const double sign = lane_id > 0 ? 1.0 : -1.0;
  double t = 0.0;
  for (int k = 1; k < std::abs(lane_id); ++k) t += lane_width_at(road, section, static_cast<int>(sign) * k, s);
  t += 0.5 * lane_width_at(road, section, lane_id, s);
  return lane_offset_at(road, s) + sign * t;
}

RefPoint lane_center(const Road& road, std::size_t section, int lane_id, double s) {
  const RefPoint ref = evaluate_reference(road, s);
  const double t = lane_center_t(road, section, lane_id, s);
  return {ref.x - t * std::sin(ref.hdg), ref.y + t * std::cos(ref.hdg), ref.hdg};
}

}  // namespace fleet::map
