#!/usr/bin/env python3
"""scikit-image's SSIM with the reference settings (SPEC §10), for `fovref bench metrics` and
the SSIM cross-check test. Reads two 1-channel PFM files (luma), prints "value seconds" where
seconds is the fastest of N runs. Exit 3 when scikit-image is not installed."""
import sys
import time


def read_pfm(path):
    import numpy as np
    with open(path, "rb") as f:
        data = f.read()
    lines, offset = [], 0
    while len(lines) < 3:
        end = data.index(b"\n", offset)
        lines.append(data[offset:end].decode("ascii").strip())
        offset = end + 1
    if lines[0] != "Pf":
        raise SystemExit(f"{path}: expected a 1-channel PFM (Pf)")
    width, height = (int(v) for v in lines[1].split())
    scale = float(lines[2])
    values = np.frombuffer(data, dtype="<f4" if scale < 0 else ">f4", count=width * height,
                           offset=offset)
    return values.reshape(height, width)[::-1].astype(np.float64)  # PFM rows are bottom-up


def main():
    try:
        from skimage.metrics import structural_similarity
    except ImportError:
        sys.exit(3)
    a, b = read_pfm(sys.argv[1]), read_pfm(sys.argv[2])
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    best, value = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        value = structural_similarity(a, b, gaussian_weights=True, sigma=1.5,
                                      use_sample_covariance=False, data_range=1.0)
        best = min(best, time.perf_counter() - start)
    print(f"{value!r} {best!r}")


if __name__ == "__main__":
    main()
