# fovref's OBJ and glTF reading against a reader nobody here wrote: the Open Asset Import Library's
# command line tool (Debian: assimp-utils). For each OBJ of the quirk corpus, random concave
# polygons and a glTF node tree, assimp triangulates (`assimp export -tri`) and fovref loads and exports; both must
# give the same number of triangles (fovref's plus the zero-area ones it drops) and the same total
# area (the sum of |triangle areas|, relative difference < 1e-5), so the triangles cover the same
# surface: ear clipping, quirks, materials aside. Skipped when assimp is not installed.
source "$(dirname "$0")/lib.bash"
if ! command -v assimp >/dev/null || ! command -v python3 >/dev/null; then
  echo "skipped: assimp (Debian: assimp-utils) or python3 is not installed"
  finish
  exit $?
fi

# area_and_count OBJ: "COUNT AREA" of an OBJ's faces (triangles only; fan for others, which
# neither exporter writes).
area_and_count() {
  python3 - "$1" <<'EOF'
import sys
v, count, area = [], 0, 0.0
for line in open(sys.argv[1], errors="replace"):
    t = line.split()
    if not t:
        continue
    if t[0] == "v":
        v.append([float(x) for x in t[1:4]])
    elif t[0] == "f":
        idx = [int(c.split("/")[0]) for c in t[1:]]
        idx = [i - 1 if i > 0 else len(v) + i for i in idx]
        for k in range(1, len(idx) - 1):
            a, b, c = v[idx[0]], v[idx[k]], v[idx[k + 1]]
            u = [b[i] - a[i] for i in range(3)]
            w = [c[i] - a[i] for i in range(3)]
            n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
            area += 0.5 * (n[0] ** 2 + n[1] ** 2 + n[2] ** 2) ** 0.5
            count += 1
print(count, repr(area))
EOF
}

crosscheck() {  # FILE [must-open]: with must-open, assimp failing to open FILE is a failure
  local obj=$1 name
  name=$(basename "$obj"); name=${name%.*}
  checks=$((checks + 1))
  if ! assimp export "$obj" "$TMP/$name-assimp.obj" -tri >/dev/null 2>&1; then
    if [ "${2:-}" = must-open ]; then
      echo "FAIL: $name: assimp does not open it"; failures=$((failures + 1))
    else
      echo "skipped $name: assimp does not open it"
    fi
    return
  fi
  if ! "$FOVREF" scene export "$obj" "$TMP/$name-fovref" >/dev/null 2>&1; then
    echo "FAIL: $name: assimp opens it, fovref does not"; failures=$((failures + 1))
    return
  fi
  local dropped theirs ours
  dropped=$("$FOVREF" scene info --json "$obj" 2>/dev/null |
    python3 -c "import json, sys; print(json.load(sys.stdin)['dropped']['zero_area_triangles'])")
  read -r theirs_count theirs_area <<<"$(area_and_count "$TMP/$name-assimp.obj")"
  read -r ours_count ours_area <<<"$(area_and_count "$TMP/$name-fovref/scene.obj")"
  if [ $((ours_count + dropped)) -ne "$theirs_count" ] ||
    ! python3 -c "import sys; a, b = $ours_area, $theirs_area; sys.exit(0 if abs(a - b) <= 1e-5 * max(a, b) else 1)"; then
    echo "FAIL: $name: fovref $ours_count triangles (+$dropped dropped), area $ours_area;" \
      "assimp $theirs_count, area $theirs_area"
    failures=$((failures + 1))
  fi
}

for obj in "$SRC"/tests/scene/obj-quirks/*.obj; do
  case "$(basename "$obj")" in
    utf16.obj | only-lines.obj) ;;  # refused by fovref by design (docs/obj-quirks.md)
    *) crosscheck "$obj" ;;
  esac
done

# Random star-shaped polygons (simple, mostly concave), one face each, in planes of every
# orientation: ear clipping must cover exactly the polygon, as assimp's does.
python3 - "$TMP" <<'EOF'
import math, random, sys
random.seed(18)
for trial in range(12):
    n = random.randint(5, 40)
    angles = sorted(random.uniform(0, 2 * math.pi) for _ in range(n))
    points = [(r * math.cos(a), r * math.sin(a)) for a, r in
              ((a, random.uniform(0.3, 1.3)) for a in angles)]
    axis = trial % 3
    with open(f"{sys.argv[1]}/star{trial}.obj", "w") as f:
        for x, y in points:
            p = [x, y, 0.5 * trial]
            p = p[3 - axis:] + p[:3 - axis]  # the polygon's plane cycles through xy, zx, yz
            f.write("v %.6f %.6f %.6f\n" % tuple(p))
        f.write("f " + " ".join(str(k + 1) for k in range(n)) + "\n")
EOF
for k in $(seq 0 11); do crosscheck "$TMP/star$k.obj" must-open; done

# glTF: a node tree with TRS (a non-trivial quaternion, non-uniform scale), a matrix and a mirror,
# indexed triangles (unsigned short), a strip and a fan. Beyond count and area, the triangles must
# be the same, corner for corner (as sets, rounded to 1e-4): the node transforms and the strip
# and fan conventions agree with assimp's.
python3 - "$TMP/nodes.gltf" <<'EOF'
import base64, json, math, struct, sys
positions = [
    [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)],
    [(0, 0, 0), (0, 1, 0), (1, 0, 0.2), (1, 1, 0), (2, 0, 0), (2, 1, 0.3)],
    [(0, 0, 0), (1, 0, 0), (0.7, 0.7, 0.1), (0, 1, 0), (-0.7, 0.7, 0), (-1, 0, 0.2)],
]
buffer, views, accessors = b"", [], []
def view(data):
    global buffer
    views.append({"buffer": 0, "byteOffset": len(buffer), "byteLength": len(data)})
    buffer += data + b"\0" * (-len(data) % 4)
    return len(views) - 1
for p in positions:
    accessors.append({"bufferView": view(b"".join(struct.pack("<3f", *q) for q in p)),
                      "componentType": 5126, "count": len(p), "type": "VEC3",
                      "min": [min(q[i] for q in p) for i in range(3)],
                      "max": [max(q[i] for q in p) for i in range(3)]})
accessors.append({"bufferView": view(struct.pack("<6H", 0, 1, 2, 0, 2, 3)),
                  "componentType": 5123, "count": 6, "type": "SCALAR"})
c, s = math.cos(0.3), math.sin(0.3)
gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [1, 2, 3], "children": [1],
                   "rotation": [0, math.sin(0.35), 0, math.cos(0.35)], "scale": [2, 1, 1.5]},
                  {"mesh": 1, "matrix": [1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, 0, 0.5, -1, 1],
                   "children": [2]},
                  {"mesh": 2, "translation": [-2, 0, 0], "scale": [-1, 1, 1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 3}]},
                   {"primitives": [{"attributes": {"POSITION": 1}, "mode": 5}]},
                   {"primitives": [{"attributes": {"POSITION": 2}, "mode": 6}]}],
        "buffers": [{"byteLength": len(buffer), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(buffer).decode()}],
        "bufferViews": views, "accessors": accessors}
json.dump(gltf, open(sys.argv[1], "w"))
EOF
crosscheck "$TMP/nodes.gltf" must-open
corners() {  # OBJ: its triangles as sorted corner sets, rounded
  python3 - "$1" <<'EOF'
import sys
v, tris = [], []
for line in open(sys.argv[1]):
    t = line.split()
    if t and t[0] == "v":
        v.append(tuple(round(float(x), 4) + 0.0 for x in t[1:4]))
    elif t and t[0] == "f":
        tris.append(tuple(sorted(v[int(c.split("/")[0]) - 1] for c in t[1:])))
print(sorted(tris))
EOF
}
checks=$((checks + 1))
if [ "$(corners "$TMP/nodes-assimp.obj")" != "$(corners "$TMP/nodes-fovref/scene.obj")" ]; then
  echo "FAIL: nodes.gltf: fovref's triangles are not assimp's"; failures=$((failures + 1))
fi
finish
