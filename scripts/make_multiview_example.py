#!/usr/bin/env python3
"""Builds the multi-view example from the blender-room case (issue 19).

    scripts/make_multiview_example.py [SRC] [OUT]

SRC (default ../shared/data/examples/blender-room, from the repository root) holds view0's
photo, camera and labels in scene.json, and novel0 / novel1 (gt/novel<k>.png, the camera
cameras/novel<k>.json, the labels gt/novel<k>_segments.png). OUT (default build/multiview-example)
gets two cases that differ only in their input views, both with novel1 held back as the novel
view that `photoscene run` / `eval` score (OUT/<case>/gt/novel1.{png,exr}, cameras/novel1.json):

    OUT/two-views/scene.json    views: view0, novel0
    OUT/view0-only/scene.json   views: view0

Every other path points back into SRC (relative), so nothing large is copied but the held-back
view. Exit status 2 with a message naming the file when SRC lacks a piece.
"""
import json
import os
import shutil
import sys


def fail(path, what):
    print(f"make_multiview_example: {path}: {what}", file=sys.stderr)
    sys.exit(2)


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        fail(path, f"expected a JSON file ({e})")


def require(path):
    if not os.path.isfile(path):
        fail(path, "missing")
    return path


def write_case(out, name, scene, src, held_back):
    case = os.path.join(out, name)
    tmp = case + ".tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(os.path.join(tmp, "gt"))
    os.makedirs(os.path.join(tmp, "cameras"))
    for ext in ("png", "exr"):
        shutil.copyfile(os.path.join(src, "gt", f"{held_back}.{ext}"),
                        os.path.join(tmp, "gt", f"{held_back}.{ext}"))
    shutil.copyfile(os.path.join(src, "cameras", f"{held_back}.json"),
                    os.path.join(tmp, "cameras", f"{held_back}.json"))
    # paths relative to the case folder (scene.json's folder), pointing into SRC
    rel = lambda p: os.path.relpath(os.path.join(src, p), case)
    s = json.loads(json.dumps(scene))
    s["geometry"] = rel(s["geometry"])
    env = s.get("lights", {}).get("environment", {})
    if "image" in env:
        env["image"] = rel(env["image"])
    for v in s["views"]:
        v["image"] = rel(v["image"])
        if "segments" in v:
            v["segments"] = rel(v["segments"])
    with open(os.path.join(tmp, "scene.json"), "w") as f:
        json.dump(s, f, indent=1)
        f.write("\n")
    shutil.rmtree(case, ignore_errors=True)
    os.rename(tmp, case)
    return case


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    src = os.path.abspath(sys.argv[1] if len(sys.argv) > 1
                          else os.path.join(root, "..", "shared", "data", "examples", "blender-room"))
    out = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "build", "multiview-example"))
    scene = read_json(require(os.path.join(src, "scene.json")))
    parts = read_json(require(os.path.join(src, "gt", "parts.json")))
    if not isinstance(parts.get("parts"), dict):
        fail(os.path.join(src, "gt", "parts.json"), "expected an object 'parts' (part -> {label, kind})")
    for k in ("novel0", "novel1"):
        require(os.path.join(src, "gt", f"{k}.png"))
        require(os.path.join(src, "cameras", f"{k}.json"))
    require(os.path.join(src, "gt", "novel0_segments.png"))
    if len(scene.get("views", [])) != 1:
        fail(os.path.join(src, "scene.json"), "expected exactly one view (view0)")

    # novel0 as an input view: its photo, camera and labels; every surface part pinned by its
    # label value as view0 pins them (emitters left to the IoU match, as in view0)
    pinned = {str(p["label"]): name for name, p in parts["parts"].items()
              if p.get("kind") in ("room", "furniture", "window")}
    novel0 = {
        "image": "gt/novel0.png",
        "color_space": "srgb",
        "camera": read_json(os.path.join(src, "cameras", "novel0.json")),
        "segments": "gt/novel0_segments.png",
        "segment_parts": dict(sorted(pinned.items())),
    }
    two = dict(scene)
    two["views"] = [scene["views"][0], novel0]
    os.makedirs(out, exist_ok=True)
    for name, s in (("two-views", two), ("view0-only", scene)):
        case = write_case(out, name, s, src, "novel1")
        print(os.path.join(case, "scene.json"))


if __name__ == "__main__":
    main()
