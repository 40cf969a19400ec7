#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""What a run leaves behind: images (.npy, .png), data files and the JSON of SPEC 9.

Every file goes through one writer, `atomic(path)`, that writes a temporary name in the same
folder and renames it over the target when the write completed: an interrupted run (Ctrl-C,
a full disk) leaves complete files or none, never a truncated one.
"""

import contextlib
import csv
import io
import json
import math
import os
import tempfile

import numpy as np
import pmt

from . import runtime
from .nrsar_python import tag_keys
from .options import MODES


@contextlib.contextmanager
def atomic(path, mode=None):
    """Yields a temporary path (same folder, same extension, so numpy and matplotlib pick
    the format from it); renames it to path on success, removes it on any exception.
    mode: the file's mode (default: readable by all, as the umask allows; 0o600 for a key)."""
    folder, name = os.path.split(os.path.abspath(path))
    ext = os.path.splitext(name)[1]
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=f".part{ext}", dir=folder)
    os.close(fd)
    try:
        yield tmp
        # mkstemp's 0600 would hide results from others
        os.chmod(tmp, 0o666 & ~_umask() if mode is None else mode)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_npy(path, array):
    with atomic(path) as tmp:
        np.save(tmp, array)
    return path


def write_bytes(path, data):
    with atomic(path) as tmp:
        with open(tmp, "wb") as f:
            f.write(data)
    return path


def write_text(path, text):
    with atomic(path) as tmp:
        with open(tmp, "w") as f:
            f.write(text)
    return path


def write_json(path, obj):
    return write_text(path, json.dumps(obj, indent=1) + "\n")


def write_csv(path, rows):
    """rows (dicts with the same keys, in the first row's order) as a CSV with a header."""
    text = io.StringIO()
    w = csv.DictWriter(text, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)
    return write_text(path, text.getvalue())


def save_figure(fig, path, **kwargs):
    """matplotlib's savefig through the atomic writer."""
    with atomic(path) as tmp:
        fig.savefig(tmp, **kwargs)
    return path


def write_png(path, image, range_axis, azimuth_axis, title, azimuth_limits=None,
              floor_db=-40):
    """Image in dB re its peak, slant range across, along-track position down."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    power_db = 20 * np.log10(np.abs(image) + 1e-30)
    power_db -= power_db.max()
    k, m = image.shape[1], image.shape[0]
    extent = [range_axis[0] - range_axis[1] / 2, range_axis[0] + range_axis[1] * (k - 0.5),
              azimuth_axis[0] + azimuth_axis[1] * (m - 0.5), azimuth_axis[0] - azimuth_axis[1] / 2]
    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.imshow(power_db, aspect="auto", extent=extent, vmin=floor_db, vmax=0,
                   cmap="viridis", interpolation="nearest")
    if azimuth_limits:
        ax.set_ylim(max(azimuth_limits), min(azimuth_limits))
    ax.set_xlabel("slant range [m]")
    ax.set_ylabel("along-track position [m]")
    ax.set_title(title, fontsize=10)
    fig.colorbar(im, ax=ax, label="power [dB re peak]")
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def azimuth_axis_of(sink, fallback):
    """[first, step] of the focused image's azimuth axis from the focuser's tag."""
    for tag in sink.tags():
        if pmt.eq(tag.key, pmt.intern(tag_keys.azimuth_axis)):
            return [pmt.to_double(pmt.tuple_ref(tag.value, 0)),
                    pmt.to_double(pmt.tuple_ref(tag.value, 1))]
    return fallback


METRIC_KEYS = ("nmse_db", "nmse_theory_db", "nmse_theory_band_db", "nmse_minus_theory_band_db",
               "pel_db", "snr_out_db", "islr_db", "pslr_db", "irw_range_m", "irw_azimuth_m",
               "peak_error_m")
# the second paper's extended-scene figures (section 3.2.1; docs/blocks/nmse_probe.md)
METRIC_KEYS += ("image_entropy", "nesz_db", "epi")


def flight_rms_deviation_m(sc, n=1000):
    """The true path's rms distance from its least-squares straight line over the aperture
    (0 on the ideal line)."""
    if sc.trajectory.is_ideal():
        return 0.0
    return float(sc.trajectory.rms_deviation_m(0.0, sc.geo.aperture_s, n))


def nav_rms_error_m(sc, n=1000):
    """rms over the aperture (n instants) of |navigation - truth| [m]."""
    if sc.navigation.is_ideal() and sc.trajectory.is_ideal():
        return 0.0
    import numpy as np
    t = list(np.linspace(0.0, sc.geo.aperture_s, n))
    d = np.array(sc.navigation.positions(t)) - np.array(sc.trajectory.positions(t))
    return float(np.sqrt(np.mean(np.sum(d * d, axis=1))))


def _json_number(x):
    """x, or None where it is not finite (JSON has no NaN)."""
    return x if math.isfinite(x) else None


def image_results(opts, chain, sc, runtime_s):
    """After the run: writes the .npy/.png files into opts.out and returns the JSON dict of
    SPEC 9 (the image metrics of the first target, the files and the axes)."""
    num, geo, scn = sc.num, sc.geo, sc.scene
    rx_times = runtime.rx_block_times(chain)
    rif, probe, foc = chain["range_ifft"], chain["probe"], chain["focuser"]
    # The image (and the range-compressed data written with it) keeps the crop's inner
    # bins; the focuser dropped guard bins on each side.
    k = foc.num_output_bins()
    guard = foc.config().guard_bins if opts.focuser == "rd" else 0
    range_axis = [rif.range_axis_first_m() + guard * rif.range_bin_m(), rif.range_bin_m()]
    slow_time_axis = [geo.track_start_m, geo.velocity_mps * num.symbol_s() * sc.pulse_symbols]
    if opts.presum_domain == "tf":  # presummed before the IFFT
        slow_time_axis[1] *= opts.presum_factor()
    keep = opts.images != "none"
    if keep:
        compressed = np.asarray(chain["range_sink"].data(), dtype=np.complex64).reshape(
            -1, rif.num_bins())[:, guard:guard + k]
        image = np.asarray(chain["image_sink"].data(), dtype=np.complex64).reshape(-1, k)
        azimuth_axis = azimuth_axis_of(chain["image_sink"], slow_time_axis)
    else:  # null sinks: the probe's line count and the focuser's axis
        step = 1 if opts.focuser == "rd" else opts.bp_line_step
        image = np.zeros((foc.lines_per_aperture() // step, 0), np.complex64)
        compressed = None
        azimuth_axis = [geo.track_start_m + foc.line_shift() * foc.pulse_interval_s() *
                        geo.velocity_mps, step * foc.pulse_interval_s() * geo.velocity_mps]

    warnings = list(sc.warnings)
    # The image's columns: slant range (range_axis_m), or on a ground grid ground range x
    # (ground_range_axis_m; range_axis_m stays the range-compressed data's slant axis).
    ground = getattr(opts, "image_grid", "slant") == "ground"
    column_axis = [foc.ground_first_x_m(), foc.ground_spacing_m()] if ground else range_axis
    if ground:
        warnings.append("the probe's point-target model is on the slant grid: the metrics of a "
                        "ground-grid image are left out (null)")
    ref_y = scn.targets[0].y_m
    last_y = azimuth_axis[0] + azimuth_axis[1] * (image.shape[0] - 1)
    if not azimuth_axis[0] <= ref_y <= last_y:
        warnings.append(
            f"the reference target (y = {ref_y:g} m) is outside the focused image "
            f"[{azimuth_axis[0]:.1f}, {last_y:.1f}] m: the scene spans more along-track than "
            f"one aperture covers; lengthen --aperture-s or image fewer targets")

    files = {}
    ys = [t.y_m for t in scn.targets]
    label = f"{opts.filter.upper()}, {opts.modulation}, SNR_in {opts.snr_db:g} dB"
    for name, data, axis, title, limits in (
            ("range_compressed", compressed, slow_time_axis, "range-compressed", None),
            ("image", image, azimuth_axis, "focused image", (min(ys) - 15, max(ys) + 15))):
        if not keep:
            files[name + "_npy"] = files[name + "_png"] = None
            continue
        files[name + "_npy"] = write_npy(os.path.abspath(os.path.join(opts.out, name + ".npy")),
                                         data)
        files[name + "_png"] = os.path.abspath(os.path.join(opts.out, name + ".png"))
        write_png(files[name + "_png"], data, column_axis if name == "image" else range_axis,
                  axis, f"{title}, {label}", azimuth_limits=limits)

    metrics = {key: float(value) for key, value in probe.metrics().items()}
    result = {
        "preset": opts.preset,
        "filter": opts.filter,
        "modulation": opts.modulation,
        "mode": opts.mode,
        "snr_db": opts.snr_db,
        "symbols": sc.symbols,
        "subcarriers": num.num_subcarriers,
        "range_bins": k,
        "range_fft_size": rif.fft_size(),
        "azimuth_lines": image.shape[0],
        "runtime_s": runtime_s,
        # receive chain alone = CPU time in work() of its blocks (perf counters)
        "rx_runtime_s": sum(rx_times.values()),
        "rx_block_s": rx_times,
        "image_npy": files["image_npy"],
        "image_png": files["image_png"],
        "range_compressed_npy": files["range_compressed_npy"],
        "range_compressed_png": files["range_compressed_png"],
        "range_axis_m": range_axis,
        "azimuth_axis_m": azimuth_axis,
        "doppler_band_hz": [foc.band_lo_hz(), foc.band_hi_hz()],
        "rcmc_applied": bool(foc.rcmc_applied()) if opts.focuser == "rd" else False,
        "focuser": opts.focuser,
        "moco": opts.moco,
        "image_grid": "ground" if ground else "slant",
        "autofocus": opts.autofocus,
        "nonfinite": chain["echo"].nonfinite_count() + chain["filter"].nonfinite_count(),
        "empty_res": chain["filter"].empty_re_count(),
        "warnings": warnings,
        "presum": opts.presum,
        "decim": opts.presum_factor(),
        "trajectory_rms_dev_m": flight_rms_deviation_m(sc),
        "nav_rms_err_m": nav_rms_error_m(sc),
    }
    if chain["presum"] is not None:
        result["warnings"] += list(chain["presum"].warnings())
    # rms of the azimuth phase error autofocus estimated (energy-weighted, rad)
    af = chain["autofocus"]
    af_rms = af.phase_rms_rad() if af is not None else math.nan
    if opts.autofocus == "trajectory":
        # the focuser's own estimate: rms line-of-sight displacement, and its two-way phase
        los = chain["focuser"].trajectory_los_rms_m()
        result["autofocus_los_rms_m"] = _json_number(los)
        # its standard error: a correction not above autofocus_significance of them is
        # not kept (autofocus_los_rms_m 0)
        result["autofocus_los_se_m"] = _json_number(chain["focuser"].trajectory_se_m())
        if opts.autofocus_gcp:
            # the navigation error's constant (at the latest aperture's middle pulse) and
            # drift the ground control points fixed, (x, y, z); None where no GCP lay in
            # that aperture's image; the offset's y (e_y) and the drift's (the speed error
            # d_y) 0 unless GCPs spread along track solved them (autofocus_gcp_offset_y_se_m,
            # autofocus_gcp_drift_y_se_mps their standard errors, else None): GCPs at one
            # along-track position see an along-track offset as a drift, and take it out
            # as one (docs/blocks/bp_focuser.md, "The along-track offset")
            foc = chain["focuser"]
            result["autofocus_gcp_used"] = foc.trajectory_gcp_used()
            for key, v in (("offset_m", foc.trajectory_gcp_offset_m()),
                           ("drift_mps", foc.trajectory_gcp_drift_mps())):
                result[f"autofocus_gcp_{key}"] = (list(v) if all(map(math.isfinite, v))
                                                  else None)
            se = foc.trajectory_gcp_se()
            result["autofocus_gcp_offset_se_m"] = _json_number(se[0])
            result["autofocus_gcp_drift_se_mps"] = _json_number(se[1])
            result["autofocus_gcp_offset_y_se_m"] = _json_number(se[2])
            result["autofocus_gcp_drift_y_se_mps"] = _json_number(se[3])
        af_rms = 4.0 * math.pi * los / sc.geo.wavelength_m()
    result["autofocus_phase_rms_rad"] = _json_number(af_rms)
    # symbols a radio's overflow lost, zeroed by ofdm_demod (docs/recording.md, "Gaps")
    demod = chain.get("radar_demod", chain["echo"])  # nrsar-isac's echo is td_echo
    lost = demod.lost_symbols() if hasattr(demod, "lost_symbols") else 0
    result["lost_symbols"] = int(lost)
    if lost:
        result["warnings"].append(
            f"{lost} of {sc.symbols} symbols lost (radio overflows), zeroed in the aperture: "
            f"the point target's peak falls by {-20 * math.log10(1 - lost / sc.symbols):.3g} "
            f"dB (1 - L/M)")
    metrics["nmse_minus_theory_band_db"] = metrics.get("nmse_db", math.nan) - metrics.get(
        "nmse_theory_band_db", math.nan)
    if ground:
        metrics = {}
    for key in METRIC_KEYS:
        value = metrics.get(key, float("nan"))
        result[key] = _json_number(value)
    if MODES[opts.mode][0] != "data":
        # SPEC 8's theory is that of data-aided grids
        result["nmse_theory_db"] = result["nmse_theory_band_db"] = None
        result["nmse_minus_theory_band_db"] = None
    if ground:
        result["ground_range_axis_m"] = column_axis
    # after the images are written, so the .npy/.png step counts too
    result["peak_rss_mb"] = runtime.peak_rss_mb()
    return result
