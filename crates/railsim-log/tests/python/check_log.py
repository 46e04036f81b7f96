#!/usr/bin/env python3
"""Independent check of a railsim log with the Python `mcap` package (not railsim's reader).

Usage: check_log.py LOG.mcap TOPIC=COUNT [TOPIC=COUNT ...]

Reads LOG with mcap.reader.make_reader (summary + index), checks the message count of every
listed topic (and that no other topic exists), that log_time == publish_time == the message's own
time, schema names and encodings, decodes the JSON of a few messages written by
`cargo run -p railsim-log --example write_sample` and compares them with the values that example
computes, and checks the scene metadata and attachment. Exits 1 on any mismatch.
"""

import json
import math
import sys

from mcap.reader import make_reader

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def close(a, b, tol=1e-12):
    return abs(a - b) <= tol * max(1.0, abs(a), abs(b))


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    path = sys.argv[1]
    expected = {}
    for arg in sys.argv[2:]:
        topic, _, count = arg.rpartition("=")
        expected[topic] = int(count)

    counts = {}
    first = {}
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        check(summary is not None, "the log has no summary")
        for schema, channel, message in reader.iter_messages():
            topic = channel.topic
            counts[topic] = counts.get(topic, 0) + 1
            check(channel.message_encoding == "json", f"{topic}: message encoding {channel.message_encoding}")
            check(schema.encoding == "jsonschema", f"{topic}: schema encoding {schema.encoding}")
            check(message.log_time == message.publish_time, f"{topic}: log_time != publish_time")
            body = json.loads(message.data)
            t_s = message.log_time * 1e-9
            if schema.name == "foxglove.FrameTransform":
                stamp = body["timestamp"]
                check(stamp["sec"] * 1_000_000_000 + stamp["nsec"] == message.log_time,
                      f"/tf timestamp {stamp} != log time {message.log_time}")
            else:
                check(close(body["t_s"], t_s), f"{topic}: t_s {body['t_s']} != log time {t_s}")
            if message.log_time == 250_000_000:
                first.setdefault(topic, []).append((schema.name, body))

        names = {topic: s for topic, s in [
            ("/bodies/wheelset_0", "railsim.BodyState"),
            ("/tf", "foxglove.FrameTransform"),
            ("/contact/0/left", "railsim.PatchMessage"),
            ("/wheelsets/0", "railsim.WheelsetMessage"),
        ]}
        for topic, schema_name in names.items():
            got = [s for s, _ in first.get(topic, [])]
            check(got and all(s == schema_name for s in got), f"{topic}: schema names {got}")

        # Values at t = 0.25 s, as write_sample computes them.
        t = 0.25
        y = 1e-3 * math.sin(2 * math.pi * 2 * t)
        ws = [b for _, b in first.get("/bodies/wheelset_0", [])]
        check(len(ws) == 1, f"/bodies/wheelset_0 at 0.25 s: {len(ws)} messages")
        if ws:
            b = ws[0]
            check(b["name"] == "wheelset_0", f"body name {b['name']}")
            check(close(b["position"][0], 55.0 * t), f"wheelset x {b['position'][0]}")
            check(close(b["position"][1], y) or abs(b["position"][1] - y) < 1e-18, f"wheelset y {b['position'][1]} vs {y}")
            check(close(b["position"][2], 0.46), f"wheelset z {b['position'][2]}")
            check(set(b["orientation"]) == {"x", "y", "z", "w"}, f"orientation keys {b['orientation']}")
        tf = [b for _, b in first.get("/tf", [])]
        check(len(tf) == 2 and {m["child_frame_id"] for m in tf} == {"wheelset_0", "bogie_0"},
              f"/tf at 0.25 s: {tf}")
        for m in tf:
            check(m["parent_frame_id"] == "track", f"/tf parent {m['parent_frame_id']}")
        left = [b for _, b in first.get("/contact/0/left", [])]
        check([p["patch"] for p in left] == [0, 1], f"left patches {[p.get('patch') for p in left]}")
        for p in left:
            check(p["side"] == "left" and p["wheelset"] == 0, f"patch ids {p}")
            check(close(p["fn_n"], 27_250.0), f"patch Fn {p['fn_n']}")
            tg = -(p["fx_n"] * p["creepages"]["xi"] + p["fy_n"] * p["creepages"]["eta"])
            check(close(p["wear_number_n"], tg), f"wear number {p['wear_number_n']} vs {tg}")
        wsm = [b for _, b in first.get("/wheelsets/0", [])]
        if wsm:
            check(close(wsm[0]["y_over_q_right"], -1000.0 / 54_500.0), f"Y/Q right {wsm[0]['y_over_q_right']}")
        else:
            failures.append("/wheelsets/0: no message at 0.25 s")

        # Self-description: the scene metadata and the attached TOML.
        metadata = {m.name: m.metadata for m in reader.iter_metadata()}
        check(metadata.get("scene", {}).get("speed_m_s") == "55", f"scene metadata {metadata.get('scene')}")
        check(metadata.get("railsim_log", {}).get("format_version") == "2",
              f"railsim_log metadata {metadata.get('railsim_log')}")
        attachments = {a.name: a for a in reader.iter_attachments()}
        toml = attachments.get("scene.toml")
        check(toml is not None and b"speed_m_s" in toml.data and toml.media_type == "application/toml",
              "scene.toml attachment")

    for topic, n in sorted(expected.items()):
        check(counts.get(topic, 0) == n, f"{topic}: {counts.get(topic, 0)} messages, expected {n}")
    for topic in sorted(set(counts) - set(expected)):
        failures.append(f"unexpected topic {topic} ({counts[topic]} messages)")
    stats = summary.statistics if summary else None
    check(stats is not None and stats.message_count == sum(expected.values()),
          f"summary statistics message_count {stats and stats.message_count}")

    if failures:
        for f in failures:
            print(f"check_log.py: {path}: {f}", file=sys.stderr)
        return 1
    print(f"check_log.py: {path}: {sum(counts.values())} messages on {len(counts)} topics OK (Python mcap)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
