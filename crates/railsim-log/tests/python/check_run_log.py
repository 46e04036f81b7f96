#!/usr/bin/env python3
"""Independent check of a log written by `railsim run`, with the Python `mcap` package.

Usage: check_run_log.py LOG.mcap [--rails]

Checks that the log has a summary whose per-channel message counts equal the messages actually
read, that the six kinds of topics are there (/bodies/*, /bogie_frames/*, /carbody/*, /contact/*,
/wheelsets/*, /tf), that the carbody's and the bogie frames' accelerometers read on average about
+g vertically (9.81 ± 0.2 m/s²), that
every message decodes as JSON with its own time equal to the log time, that no number is NaN or
infinite, and that the `scene` and `railsim_result` metadata (with the state digest) are present.
Messages on /elements/* (force elements) must name their element, carry a known type, the
vectors of three numbers and the state exactly where the type has one, a dissipation_w never
negative, a cumulative dissipated_j that never falls, cumulative work_j and dissipated_j equal
to the trapezoidal integrals of power_w and dissipation_w over the messages so far when the run
integrated them over the log's samples (the scene metadata's `assessment_rate_hz` equal to its
`log_rate_hz`; at a multiple of it the run integrates over samples the log does not hold, and
that equality is not checked), and a friction element's
force must stay within its sliding force.
With --rails (a run on an elastic rail support, logging bodies, carbody, contact, elements and
wheelsets): /tf and /bogie_frames are not required, /elements/* is, and every /wheelsets message
must carry
`rail_displacement_m`, four finite numbers with both rails below their unloaded height. Exits 1 on any mismatch.
"""

import json
import math
import sys

from mcap.reader import make_reader


def finite(v):
    if isinstance(v, float):
        return math.isfinite(v)
    if isinstance(v, dict):
        return all(finite(x) for x in v.values())
    if isinstance(v, list):
        return all(finite(x) for x in v)
    return True


ELEMENT_TYPES = {"bushing", "table", "series_spring_damper", "damper", "friction",
                 "planar_friction", "rotational_friction", "anti_roll_bar"}
WITH_STATE = {"series_spring_damper", "friction", "planar_friction", "rotational_friction"}


def check_element(topic, body):
    """A /elements/<name> message: its name, a known type, three numbers per vector, the state
    present exactly for the elements that carry one (a damper may or may not), and a friction
    element within its sliding force."""
    out = []
    kind = body.get("type")
    if topic != "/elements/" + str(body.get("element")):
        out.append(f"{topic}: element name {body.get('element')!r}")
    if kind not in ELEMENT_TYPES:
        out.append(f"{topic}: unknown type {kind!r}")
    for key in ("deflection_m", "deflection_rate_m_s", "rotation_rad", "force_n", "moment_nm"):
        v = body.get(key)
        if not (isinstance(v, list) and len(v) == 3):
            out.append(f"{topic}: {key} = {v!r}")
    if kind != "damper" and (kind in WITH_STATE) != ("state_m" in body):
        out.append(f"{topic}: state_m for a {kind}: {body.get('state_m')!r}")
    for ftype, limit, key in (("friction", "sliding_force_n", "force_n"),
                              ("planar_friction", "sliding_force_n", "force_n"),
                              ("rotational_friction", "sliding_moment_nm", "moment_nm")):
        if kind == ftype:
            f0 = body.get(limit)
            if f0 is None or math.hypot(*body[key]) > 1.01 * f0 + 1e-6:
                out.append(f"{topic}: friction {key} {body[key]} beyond {limit} {f0}")
    return out


def check_work(topic, body, work, exact):
    """An element never dissipates a negative power, its cumulative dissipated_j never falls, and
    with `exact` its cumulative work_j and dissipated_j are the trapezoidal integrals of its
    power_w and dissipation_w over the messages so far (recomputed here; `work` keeps per topic
    the last time, powers and sums, and the last logged dissipated_j)."""
    keys = ("power_w", "dissipation_w", "work_j", "dissipated_j")
    v = [body.get(k) for k in keys]
    if not all(isinstance(x, (int, float)) for x in v):
        return [f"{topic}: {dict(zip(keys, v))!r}"]
    p, d, w, e = v
    t = body["t_s"]
    t0, p0, d0, w0, e0, last_e = work.get(topic, (t, p, d, 0.0, 0.0, e))
    acc = (w0 + 0.5 * (t - t0) * (p0 + p), e0 + 0.5 * (t - t0) * (d0 + d))
    work[topic] = (t, p, d) + acc + (e,)
    out = []
    if d < 0.0:
        out.append(f"{topic}: dissipation_w {d} at {t} s")
    if e < last_e - 1e-12 * max(1.0, abs(last_e)):
        out.append(f"{topic}: dissipated_j falls from {last_e} to {e} at {t} s")
    if exact:
        for name, logged, ours in (("work_j", w, acc[0]), ("dissipated_j", e, acc[1])):
            if abs(ours - logged) > 1e-9 * max(1.0, abs(ours)):
                out.append(f"{topic}: {name} {logged} at {t} s, the trapezoidal integral {ours}")
    return out


def main():
    rails = sys.argv[2:] == ["--rails"]
    if len(sys.argv) != 2 and not rails:
        print(__doc__, file=sys.stderr)
        return 2
    failures = []
    counts = {}
    work = {}
    vertical = []
    frames = []
    with open(sys.argv[1], "rb") as f:
        names = {m.name: m.metadata for m in make_reader(f).iter_metadata()}
        scene = names.get("scene", {})
        rates = (scene.get("log_rate_hz"), scene.get("assessment_rate_hz", scene.get("log_rate_hz")))
        exact = rates[0] is not None and float(rates[0]) == float(rates[1])
        f.seek(0)
        reader = make_reader(f)
        summary = reader.get_summary()
        if summary is None or summary.statistics is None:
            print("check_run_log: the log has no summary statistics")
            return 1
        for schema, channel, message in reader.iter_messages():
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            body = json.loads(message.data)
            if not finite(body):
                failures.append(f"{channel.topic}: non-finite number at {message.log_time}")
            if rails and channel.topic.startswith("/wheelsets/"):
                d = body.get("rail_displacement_m")
                if not (isinstance(d, list) and len(d) == 4 and d[1] < 0 and d[3] < 0):
                    failures.append(f"{channel.topic}: rail_displacement_m = {d!r}")
            if channel.topic.startswith("/carbody/"):
                vertical.append(body["vertical_m_s2"])
            if channel.topic.startswith("/bogie_frames/"):
                frames.append(body["vertical_m_s2"])
            if channel.topic.startswith("/elements/"):
                failures.extend(check_element(channel.topic, body))
                failures.extend(check_work(channel.topic, body, work, exact))
            if schema.name == "foxglove.FrameTransform":
                st = body["timestamp"]
                ok = st["sec"] * 1_000_000_000 + st["nsec"] == message.log_time
            else:
                ok = abs(body["t_s"] - message.log_time * 1e-9) <= 1e-9
            if not ok:
                failures.append(f"{channel.topic}: message time differs from log time")
        stated = {summary.channels[cid].topic: n
                  for cid, n in summary.statistics.channel_message_counts.items()}
        for topic, n in stated.items():
            if counts.get(topic, 0) != n:
                failures.append(f"{topic}: summary says {n} messages, read {counts.get(topic, 0)}")
        for prefix in ("/bodies/", "/carbody/", "/contact/", "/wheelsets/") + (
                ("/elements/",) if rails else ("/bogie_frames/", "/tf")):
            if not any(t.startswith(prefix) for t in counts):
                failures.append(f"no topic {prefix}*")
        if vertical and abs(sum(vertical) / len(vertical) - 9.81) > 0.2:
            failures.append(f"carbody: mean vertical reading {sum(vertical) / len(vertical)} m/s²")
        if frames and abs(sum(frames) / len(frames) - 9.81) > 0.2:
            failures.append(f"bogie frames: mean vertical reading {sum(frames) / len(frames)} m/s²")
        if work and not exact:
            print(f"check_run_log: the run integrated the elements' work over its samples at "
                  f"{rates[1]} Hz, the log holds them at {rates[0]} Hz: work_j and dissipated_j "
                  f"not checked against the log's trapezoidal integrals")
        if "scene" not in names:
            failures.append("no scene metadata")
        if len(names.get("railsim_result", {}).get("state_digest", "")) != 16:
            failures.append("no state digest in railsim_result metadata")
    for msg in failures[:20]:
        print("check_run_log:", msg)
    print(f"check_run_log: {sum(counts.values())} messages on {len(counts)} topics, "
          f"{len(failures)} problems")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
