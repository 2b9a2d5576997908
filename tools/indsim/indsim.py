#!/usr/bin/env python3
"""A second, independent simulator of a filmed rolling ring, for checking that ringlab's
diagnosis generalises beyond recordings it made itself.

Written apart from ringlab's Rust code: general Newton-Euler equations about the centre of
mass with the contact force as an unknown (a 6x6 linear system per evaluation, not the paper's
closed form), scipy's DOP853, its own effect laws (Reynolds drag on the rim speed, friction
torques that depend on the instantaneous normal force), a hybrid rolling/sliding contact with
Coulomb friction, a pinhole camera with tilt, radial lens distortion, and a tracker's faults
(correlated noise, outliers, swapped labels, lost marks). Conventions: ../../../shared/PHYSICS.md
and RECORDING_FORMAT.md.

    python3 tools/indsim/indsim.py SPEC.json OUT_DIR

SPEC.json: {"name": {...case...}, ...}; writes OUT_DIR/name.csv and OUT_DIR/truth.json.
Needs numpy and scipy; nothing in the Rust build or tests runs it.
"""
import json
import math
import sys

import numpy as np
from scipy.integrate import solve_ivp

G_MODEL = 1.0275374  # g in mean radii per time unit^2 (the paper's R phi'^2 = 20.2 g)
G_MM = 9810.0


def cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


class Body:
    def __init__(self, shape, r_mm, h_mm, w_mm):
        self.unit_mm = r_mm - (w_mm / 2 if shape == "ring" else 0.0)
        if shape == "disk":
            self.unit_mm = r_mm
        self.R = r_mm / self.unit_mm
        self.h = h_mm / self.unit_mm
        ri = 0.0 if shape == "disk" else self.R - w_mm / self.unit_mm
        i2 = (self.R**2 + ri**2) / 2
        i1 = (self.R**2 + ri**2) / 4 + self.h**2 / 12
        self.I = np.diag([i1, i2, i1])
        self.rG = np.array([0.0, self.h / 2, self.R])
        # marks on the top edge at the wall's mean radius (a disk: its rim), as the format's
        # sample has them
        self.mark_r = self.R - (w_mm / 2 / self.unit_mm if shape == "ring" else 0.0)
        self.time_unit_s = math.sqrt(G_MODEL * self.unit_mm / G_MM)


class Model:
    """Effects (all optional): C (3), reynolds_n with reynolds_axis ('rim' or 'each'),
    rolling_k, pivot_k (arms k over R, torques k R F_N), trans_k (force -k|v|v on C),
    mu (Coulomb contact; absent: pure rolling always), table_slope (rad, about table X)."""

    def __init__(self, body, spec):
        self.b = body
        self.C = np.array(spec["C"], float)
        self.re_n = spec.get("reynolds_n", 0.0)
        self.re_axis = spec.get("reynolds_axis", "rim")
        self.rolling_k = spec.get("rolling_k", 0.0) * body.R
        self.pivot_k = spec.get("pivot_k", 0.0) * body.R
        self.trans_k = spec.get("trans_k", 0.0) / body.R
        self.mu = spec.get("mu")
        self.slope = spec.get("table_slope", 0.0)
        self.re0 = None
        J = body.I.copy()
        h, R = body.h, body.R
        J += np.array([[h * h / 4 + R * R, 0, 0], [0, R * R, -h * R / 2], [0, -h * R / 2, h * h / 4]])
        self.J = J

    def frame(self, phi, th):
        c, s = math.cos(phi), math.sin(phi)
        e1 = np.array([c, s, 0.0])
        E2 = np.array([-s, c, 0.0])
        Z = np.array([0.0, 0.0, 1.0])
        e2 = math.cos(th) * E2 + math.sin(th) * Z
        e3 = -math.sin(th) * E2 + math.cos(th) * Z
        return np.array([e1, e2, e3])  # rows: frame axes in table coordinates

    def drag_torque(self, w):
        """T with J^-1 T = tau, tau_i = -C_i |w_i| w_i (eq. 5), times the Reynolds factor."""
        C = self.C.copy()
        if self.re_n > 0:
            if self.re_axis in ("rim", "centre"):
                speed = (np.linalg.norm(w) * self.b.R if self.re_axis == "rim"
                         else np.linalg.norm(cross(w, self.b.rG)))
                f = min((self.re0 / max(speed, 1e-12)) ** self.re_n, 10.0)
                C = C * f
            else:
                C = np.array([c * min((r0 / max(abs(wi), 1e-12)) ** self.re_n, 10.0)
                              for c, r0, wi in zip(C, self.re0_each, w)])
        tau = -C * np.abs(w) * w
        return self.J @ tau

    def gravity(self, F):
        """Gravity in the table frame (a tilted table: g has a component along table Y)."""
        return np.array([0.0, -math.sin(self.slope), -math.cos(self.slope)]) * G_MODEL

    def accel(self, y, mode, slip_dir=None):
        """mode 'roll': returns (dy, F(frame comps)); mode 'slide': state has vC (2 more)."""
        phi, th, psi, w1, w2, w3 = y[:6]
        b = self.b
        E = self.frame(phi, th)
        Zf = E @ np.array([0.0, 0.0, 1.0])  # table normal in frame comps
        g_f = E @ self.gravity(None)
        w = np.array([w1, w2, w3])
        Om = np.array([w1, w3 * math.tan(th), w3])  # (theta', phi' sin th, phi' cos th)
        T = self.drag_torque(w)
        if mode == "roll":
            vC = cross(w, b.rG)
        else:
            vC_t = np.array([y[8], y[9], self._vz(th, w1)])
            vC = E @ vC_t
        Fair = -self.trans_k * np.linalg.norm(vC) * vC
        # Torques k F_N along fixed directions (F_N = F.Z, linear in the unknowns).
        dirs = []
        if self.rolling_k > 0:
            horiz = w - (w @ Zf) * Zf
            n = np.linalg.norm(horiz)
            if n > 1e-9:
                dirs.append(-self.rolling_k * horiz / n * math.tanh(n / 1e-3))
        if self.pivot_k > 0:
            wz = w @ Zf
            dirs.append(-self.pivot_k * Zf * math.tanh(wz / 1e-3))
        Tn = sum(dirs) if dirs else np.zeros(3)
        I = b.I
        if mode == "roll":
            # Unknowns x = (wdot (3), F (3)): m(wdot x rG + Om x vC) = F + m g + Fair,
            # I wdot + Om x (I w) = -rG x F + T + Tn (Zf.F).
            A = np.zeros((6, 6))
            rhs = np.zeros(6)
            A[:3, :3] = -skew(b.rG)  # wdot x rG = -rG x wdot
            A[:3, 3:] = -np.eye(3)
            rhs[:3] = -cross(Om, vC) + g_f + Fair
            A[3:, :3] = I
            A[3:, 3:] = skew(b.rG) - np.outer(Tn, Zf)
            rhs[3:] = -cross(Om, I @ w) + T
            x = np.linalg.solve(A, rhs)
            if x[3:] @ Zf < 0 and dirs:
                # the table cannot pull: no normal force, no friction torques
                A[3:, 3:] = skew(b.rG)
                x = np.linalg.solve(A, rhs)
            wdot, F = x[:3], x[3:]
            vC_t = E.T @ vC
            return wdot, F, vC_t[:2], None
        # Sliding: unknowns wdot (3), F_N; friction -mu F_N s (s: unit slip direction, table).
        vP = vC - cross(w, b.rG)  # contact point velocity, frame comps
        vP = vP - (vP @ Zf) * Zf
        if np.linalg.norm(vP) > 1e-9:
            s = vP / np.linalg.norm(vP)
        else:
            # from rest of the contact: friction along the demand that broke the cone
            _, F_roll, _, _ = self.accel(y[:8], "roll")
            Ft = F_roll - (F_roll @ Zf) * Zf
            s = -Ft / max(np.linalg.norm(Ft), 1e-15)
        Ff_unit = Zf - self.mu * s  # F = F_N (Z - mu s)
        # vertical: m z'' = F_N - m g_z + Fair_z, z'' = z1(th) wdot1 + z2(th) w1^2
        z1 = b.h / 2 * math.cos(th) - b.R * math.sin(th)
        z2 = -b.h / 2 * math.sin(th) - b.R * math.cos(th)
        gz = self.gravity(None)[2]
        Fair_t = E.T @ Fair
        A = np.zeros((4, 4))
        rhs = np.zeros(4)
        A[0, 0] = z1
        A[0, 3] = -Ff_unit @ Zf
        rhs[0] = -z2 * w1 * w1 + gz + Fair_t[2]
        A[1:, :3] = I
        A[1:, 3] = cross(b.rG, Ff_unit) - Tn
        rhs[1:] = -cross(Om, I @ w) + T
        x = np.linalg.solve(A, rhs)
        wdot, FN = x[:3], x[3]
        F = FN * Ff_unit
        F_t = E.T @ F
        g_t = self.gravity(None)
        a_h = F_t[:2] + g_t[:2] + Fair_t[:2]
        return wdot, F, vC_t[:2], a_h

    def _vz(self, th, w1):
        b = self.b
        return (b.h / 2 * math.cos(th) - b.R * math.sin(th)) * w1

    def rhs(self, t, y, mode):
        phi, th, psi, w1, w2, w3 = y[:6]
        wdot, F, v_xy, a_h = self.accel(y, mode)
        dphi = w3 / math.cos(th)
        dpsi = w2 - w3 * math.tan(th)
        d = [dphi, w1, dpsi, wdot[0], wdot[1], wdot[2], v_xy[0], v_xy[1]]
        if mode == "slide":
            d += [a_h[0], a_h[1]]
        return np.array(d)

    def margin(self, y):
        """mu F_N - |F_t| in rolling (negative: rolling needs more friction than there is)."""
        phi, th = y[0], y[1]
        _, F, _, _ = self.accel(y, "roll")
        Zf = self.frame(phi, th) @ np.array([0.0, 0.0, 1.0])
        FN = F @ Zf
        Ft = F - FN * Zf
        return self.mu * FN - np.linalg.norm(Ft), FN

    def slip_speed(self, y):
        phi, th = y[0], y[1]
        E = self.frame(phi, th)
        w = np.array(y[3:6])
        vC = E @ np.array([y[8], y[9], self._vz(th, y[3])])
        vP = vC - cross(w, self.b.rG)
        return np.linalg.norm(vP), vP


def simulate(body, model, y0, t_end, dt_out, start_mode="roll", rtol=1e-10):
    """Hybrid rolling/sliding run. Returns times and states (rolling states padded with vC)."""
    th_stop = math.pi / 2 - 0.02
    slides = []
    fn_min = math.inf
    w0 = np.array(y0[3:6])
    model.re0 = (np.linalg.norm(w0) * body.R if model.re_axis != "centre"
                 else np.linalg.norm(cross(w0, body.rG)))
    model.re0_each = [np.linalg.norm(y0[3:6])] * 3
    t, y, mode = 0.0, np.array(y0, float), start_mode
    if mode == "slide":
        # from zero slip: the centre moves as rolling would have it
        E = model.frame(y[0], y[1])
        vC = E.T @ cross(y[3:6], body.rG)
        y = np.concatenate([y[:8], vC[:2]])
        slides.append([0.0, None])
    ts = np.arange(0.0, t_end + 1e-12, dt_out)
    out_t, out_y, modes = [], [], []
    while t < t_end:
        def flat(tt, yy, *a):
            return yy[1] - th_stop
        flat.terminal = True

        def rest(tt, yy, *a):
            return np.linalg.norm(yy[3:6]) - 2e-3
        rest.terminal = True
        events = [flat, rest]
        if model.mu is not None:
            if mode == "roll":
                def ev(tt, yy, *a):
                    return model.margin(yy)[0]
                ev.terminal = True
                ev.direction = -1
            else:
                def ev(tt, yy, *a):
                    return model.slip_speed(yy)[0] - 1e-7
                ev.terminal = True
                ev.direction = -1
            events.append(ev)
        yy = y if mode == "slide" else y[:8]
        sol = solve_ivp(lambda tt, v: model.rhs(tt, v, mode), (t, t_end), yy, method="DOP853",
                        rtol=rtol, atol=rtol * 1e-2, events=events, dense_output=True)
        t1 = sol.t[-1]
        sel = ts[(ts >= t - 1e-12) & (ts < t1 - 1e-12)] if sol.status == 1 else ts[(ts >= t - 1e-12) & (ts <= t1 + 1e-12)]
        for tk in sel:
            if out_t and tk <= out_t[-1] + 1e-12:
                continue
            v = sol.sol(tk)
            _, F, _, _ = model.accel(v, mode)
            fn_min = min(fn_min, F @ (model.frame(v[0], v[1]) @ np.array([0.0, 0.0, 1.0])))
            out_t.append(tk)
            out_y.append(v[:8])
            modes.append(mode)
        y_end = sol.y[:, -1]
        if sol.status != 1:
            break
        fired = [i for i, e in enumerate(sol.t_events) if len(e)]
        if 0 in fired or 1 in fired:
            break
        # a switch
        if mode == "roll":
            E = model.frame(y_end[0], y_end[1])
            vC = E.T @ cross(y_end[3:6], body.rG)
            y = np.concatenate([y_end[:8], vC[:2]])
            mode = "slide"
            slides.append([t1, None])
            # nudge through the event
            t = t1
        else:
            y8 = y_end[:8].copy()
            m, _ = model.margin(y8)
            if m >= 0:
                mode = "roll"
                y = y8
                slides[-1][1] = t1
            else:
                # still beyond the cone: slide on from (nearly) zero slip
                y = y_end.copy()
            t = t1
        if len(slides) > 400:
            raise RuntimeError("too many switches")
    if fn_min < 0:
        print(f"warning: the table pulls (F_N = {fn_min:.3f} < 0): lift-off, which this simulator "
              "does not model; the recording is not physical", file=sys.stderr)
    model.fn_min = fn_min
    return np.array(out_t), np.array(out_y), slides


def marks_3d(body, y):
    """Four marks on the top edge circle (centre A), table coordinates in model units."""
    phi, th, psi = y[0], y[1], y[2]
    m = Model.frame(None, phi, th)
    e1, e2, e3 = m
    zc = body.h / 2 * math.sin(th) + body.R * math.cos(th)
    C = np.array([y[6], y[7], zc])
    A = C + body.h / 2 * e2
    b1 = math.cos(psi) * e1 - math.sin(psi) * e3
    b3 = math.sin(psi) * e1 + math.cos(psi) * e3
    r = body.mark_r
    return [A + r * (math.cos(k * math.pi / 2) * b1 + math.sin(k * math.pi / 2) * b3) for k in range(4)]


class Cam:
    def __init__(self, spec, px_per_mm, size):
        self.K = px_per_mm
        self.size = size
        self.c = np.array(size, float) / 2
        self.D = spec.get("distance_mm")
        self.tilt = math.radians(spec.get("tilt_deg", 0.0))
        self.k1 = spec.get("k1", 0.0)
        self.k2 = spec.get("k2", 0.0)
        self.dist_centre = np.array(spec.get("distortion_centre_offset_px", [0.0, 0.0])) + self.c
        self.aspect = spec.get("pixel_aspect", 1.0)
        self.roll = math.radians(spec.get("roll_deg", 0.0))

    def project(self, p_mm):
        x, y, z = p_mm
        if self.D is None:
            u = np.array([x, -y]) * self.K
        else:
            t = self.tilt
            Cc = np.array([0.0, -self.D * math.sin(t), self.D * math.cos(t)])
            a = np.array([0.0, math.sin(t), -math.cos(t)])
            ex = np.array([1.0, 0.0, 0.0])
            ey = np.array([0.0, -math.cos(t), -math.sin(t)])
            d = np.array(p_mm) - Cc
            f = self.K * self.D
            u = f * np.array([d @ ex, d @ ey]) / (d @ a)
        if self.roll:
            cr, sr = math.cos(self.roll), math.sin(self.roll)
            u = np.array([cr * u[0] - sr * u[1], sr * u[0] + cr * u[1]])
        u = u * np.array([1.0, self.aspect])
        px = self.c + u
        if self.k1 or self.k2:
            hd = 0.5 * math.hypot(*self.size)
            r = px - self.dist_centre
            rho2 = (r @ r) / hd**2
            px = self.dist_centre + r * (1 + self.k1 * rho2 + self.k2 * rho2 * rho2)
        return px


def exposed(px, sub, shutter, blur, height, n_moving, n_rest):
    """Each frame's marks as a camera exposes them: row y read `shutter` frame intervals times
    y / height after the frame's time (a rolling shutter), each mark the mean of its positions
    over `blur` of a frame interval from there (motion blur)."""
    frames = (n_moving + sub - 1) // sub + n_rest
    out = np.empty((frames, 4, 2))
    span = max(1, int(round(blur * sub)))
    for i in range(frames):
        for k in range(4):
            j = i * sub + int(round(shutter * sub * px[i * sub, k, 1] / height))
            out[i, k] = px[j:j + span, k].mean(axis=0)
    return out


def make(name, spec, rng):
    shape = spec.get("shape", "ring")
    r_mm, h_mm, w_mm = spec.get("body_mm", [20.66, 18.0, 1.0] if shape == "ring" else [31.75, 6.14, 31.75])
    body = Body(shape, r_mm, h_mm, w_mm)
    model = Model(body, spec)
    fps = spec.get("fps", 300.0)
    th0, phid0, psid0 = spec["theta0"], spec["phidot0"], spec.get("psidot0", 0.0)
    w = [0.0, phid0 * math.sin(th0) + psid0, phid0 * math.cos(th0)]
    y0 = [spec.get("phi0", rng.uniform(-math.pi, math.pi)), th0, 0.0] + w + [0.0, 0.0]
    dt_frame = 1.0 / fps / body.time_unit_s
    # a camera's exposure within the frame (rolling shutter, motion blur) needs the motion
    # between frames: `sub` samples per frame
    shutter = spec.get("rolling_shutter", 0.0)
    blur = spec.get("blur", 0.0)
    sub = 16 if (shutter or blur) else 1
    t, ys, slides = simulate(body, model, y0, spec.get("t_end", 400.0), dt_frame / sub,
                             spec.get("start_mode", "roll"), spec.get("rtol", 1e-10))
    # rest frames after the end
    n_rest = spec.get("rest_frames", 30)
    px_per_mm = spec.get("px_per_mm", 3.364764)
    size = spec.get("image_px", [1280, 1024])
    cam = Cam(spec.get("camera", {}), px_per_mm, size)
    pts = np.array([[p * body.unit_mm for p in marks_3d(body, y)] for y in ys])  # mm
    pts = np.concatenate([pts, np.repeat(pts[-1:], n_rest * sub + (2 * sub if sub > 1 else 0), axis=0)])
    # place the path: its box centred at a chosen fraction of the image (in table mm)
    lo, hi = pts[:, :, :2].reshape(-1, 2).min(0), pts[:, :, :2].reshape(-1, 2).max(0)
    span_mm = np.array(size) / px_per_mm
    where = np.array(spec.get("where", [rng.uniform(0.3, 0.7), rng.uniform(0.3, 0.7)]))
    target = (where - 0.5) * span_mm * np.array([1, -1])
    pts[:, :, :2] += target - (lo + hi) / 2
    px = np.array([[cam.project(p) for p in f] for f in pts])
    if sub > 1:
        px = exposed(px, sub, shutter, blur, size[1], len(ys), n_rest)
    if spec.get("reverse_marks"):
        px = px[:, [0, 3, 2, 1]]
    # the tracker: noise (white or correlated), quantisation, outliers, swaps, lost marks
    sigma = spec.get("noise_px", 0.5)
    corr = spec.get("noise_corr", 0.0)
    n = len(px)
    if spec.get("noise_dist") == "t3":
        # heavy tails: Student's t with 3 degrees of freedom, scaled to the same sigma
        e = rng.standard_t(3, px.shape) * sigma / math.sqrt(3.0)
    else:
        e = rng.normal(0, sigma, px.shape)
    if "noise_per_mark" in spec:
        e *= np.array(spec["noise_per_mark"])[None, :, None] / sigma
    if corr > 0:
        # AR(1) with the same marginal sigma
        for i in range(1, n):
            e[i] = corr * e[i - 1] + math.sqrt(1 - corr * corr) * e[i]
    px = px + e
    if spec.get("quantise", False):
        px = np.round(px)
    out_frac = spec.get("outliers", 0.0)
    outliers = 0
    glitch_list = []
    for i in range(n):
        for k in range(4):
            if rng.random() < out_frac:
                ang = rng.uniform(0, 2 * math.pi)
                px[i, k] += rng.uniform(10, 60) * np.array([math.cos(ang), math.sin(ang)])
                outliers += 1
                glitch_list.append([int(i), int(k), "outlier"])
    for _ in range(spec.get("swaps", 0)):
        i0 = rng.integers(0, n - 20)
        ln = rng.integers(3, 15)
        a, b = rng.choice(4, 2, replace=False)
        px[i0:i0 + ln, [a, b]] = px[i0:i0 + ln, [b, a]]
        glitch_list.append([int(i0), int(ln), f"swap {a + 1}-{b + 1}"])
    lost = np.zeros((n, 4), bool)
    lost_frac = spec.get("lost", 0.0)
    if lost_frac > 0:
        i = 0
        while i < n:
            if rng.random() < lost_frac / 5:
                k = rng.integers(0, 4)
                ln = rng.integers(1, 10)
                lost[i:i + ln, k] = True
                i += ln
            i += 1
    first = spec.get("skip_frames", 0)
    if spec.get("keep_frames"):
        n = min(n, first + spec["keep_frames"])
    header_fps = spec.get("header_fps", fps)
    lines = ["# ringlab-recording v1", f"# fps = {header_fps}", f"# px_per_mm = {px_per_mm}",
             f"# shape = {shape}", f"# outer_radius_mm = {r_mm}", f"# width_mm = {h_mm}"]
    if shape == "ring":
        lines.append(f"# thickness_mm = {w_mm}")
    lines += [f"# image_width_px = {size[0]}", f"# image_height_px = {size[1]}"]
    lines.append("frame,x1,y1,x2,y2,x3,y3,x4,y4")
    for i in range(first, n):
        row = [str(i - first)]
        for k in range(4):
            if lost[i, k]:
                row += ["", ""]
            else:
                row += [f"{px[i, k, 0]:.2f}", f"{px[i, k, 1]:.2f}"]
        lines.append(",".join(row))
    truth = {k: v for k, v in spec.items()}
    truth.update({"frames": n - first, "t_end": float(t[-1]), "time_unit_s": body.time_unit_s,
                  "slides": [[a, b] for a, b in slides], "outliers": outliers,
                  "min_normal_force": model.fn_min,
                  "glitch_list": glitch_list})
    return "\n".join(lines) + "\n", truth


def main():
    spec_path, out_dir = sys.argv[1], sys.argv[2]
    only = set(sys.argv[3:])
    specs = json.load(open(spec_path))
    import os
    os.makedirs(out_dir, exist_ok=True)
    truth_path = os.path.join(out_dir, "truth.json")
    truth = json.load(open(truth_path)) if os.path.exists(truth_path) else {}
    for name, spec in specs.items():
        if only and name not in only:
            continue
        rng = np.random.default_rng(spec.get("seed", abs(hash(name)) % 2**32))
        csv, tr = make(name, spec, rng)
        open(os.path.join(out_dir, name + ".csv"), "w").write(csv)
        truth[name] = tr
        print(name, tr["frames"], "frames, t_end", round(tr["t_end"], 2), "slides", len(tr["slides"]), flush=True)
    json.dump(truth, open(truth_path, "w"), indent=1)


if __name__ == "__main__":
    main()
