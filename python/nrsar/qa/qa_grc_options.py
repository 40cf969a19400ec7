#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Every option list of the GRC blocks held against the names the module accepts.

A grc/*.block.yml parameter of dtype enum reaches the block through its make: template, either
by one of params.py's builders (nrsar.make_X('${p}')) or as a Python literal (True / False).
Its options must be the names that builder accepts, read from the C++ side: the members of the
bound enum (lower case) or the C++ preset names; one label per option, the default among them.
A list may leave a name out only where the block refuses it (the test builds the block with
it), and may add a name the template itself tests for ('${p}' == 'file'). The values the
example flowgraphs give those parameters must be options, and their nrsar blocks and
parameters must exist in grc/.
"""

import glob
import os
import re

import yaml

from gnuradio import gr_unittest
from gnuradio import nrsar


def _repo_root():
    """The source tree (grc/*.block.yml and examples/), found upwards from this file wherever
    it lies (the build tree has grc/ and examples/ folders without them)."""
    d = os.path.dirname(os.path.abspath(__file__))
    while not (glob.glob(os.path.join(d, "grc", "*.block.yml"))
               and glob.glob(os.path.join(d, "examples", "*.grc"))):
        parent = os.path.dirname(d)
        if parent == d:
            raise RuntimeError("grc/ and examples/ not found above " + __file__)
        d = parent
    return d


ROOT = _repo_root()


def members(enum):
    """The bound C++ enum's member names, lower case, in declaration order."""
    return [name.lower() for name in enum.__members__]


# What each builder of a make: template accepts, from the bindings (not from params.py's tables).
ACCEPTED = {
    "make_numerology": list(nrsar.numerology.preset_names()),
    "make_geometry": list(nrsar.geometry.preset_names()),
    "make_dmrs": list(nrsar.dmrs_config.preset_names()),
    "make_modulation": members(nrsar.modulation),
    "make_tx_mode": members(nrsar.tx_mode),
    "make_filter": members(nrsar.filter_type),
    "make_presum_method": members(nrsar.presum_method),
    "make_presum_domain": members(nrsar.presum_domain),
    "make_doppler_band": members(nrsar.doppler_band),
    "make_colormap": members(nrsar.image_colormap),
    "make_beam": members(nrsar.beam_mode),
    "make_navigation": members(nrsar.nav_error_model),
    "make_moco_order": members(nrsar.moco_order),
    "make_pusch_coding": members(nrsar.pusch_coding),
    "make_pusch_scrambling": members(nrsar.pusch_scrambling),
    "make_autofocus_method": members(nrsar.autofocus_method),
}

# A builder's name argument passed by keyword: keyword -> builder
KEYWORD_BUILDERS = {"error": "make_navigation"}

# Names a block's list leaves out, and how to build the block with one: it must refuse it.
# PUSCH carries QPSK and QAM only (TS 38.211 6.3.1.2), and the receiver estimates the channel
# from the DMRS, so a layout without DMRS cannot be decoded.
NARROWED = {
    ("nrsar_pusch_encoder", "modulation"):
        lambda name: nrsar.pusch_encoder(nrsar.pusch_config(mod=nrsar.make_modulation(name))),
    ("nrsar_pusch_receiver", "modulation"):
        lambda name: nrsar.pusch_receiver(nrsar.pusch_config(mod=nrsar.make_modulation(name))),
    ("nrsar_pusch_receiver", "dmrs"):
        lambda name: nrsar.pusch_receiver(nrsar.pusch_config(dmrs=nrsar.make_dmrs(name))),
}

# Parameters GRC gives every block besides those of its .block.yml.
GRC_COMMON = {"alias", "comment", "affinity", "maxoutbuf", "minoutbuf"}

BUILDER = re.compile(r"nrsar\.(make_\w+)\(\s*'\$\{(\w+)\}'")
KEYWORD = re.compile(r"\b(\w+)='\$\{(\w+)\}'")
LITERAL = re.compile(r"'\$\{(\w+)\}'\s*==\s*'(\w+)'")


def load_blocks():
    blocks = {}
    for path in sorted(glob.glob(os.path.join(ROOT, "grc", "*.block.yml"))):
        with open(path) as f:
            blk = yaml.safe_load(f)
        blocks[blk["id"]] = blk
    return blocks


def enum_params(blk):
    return [p for p in blk["parameters"] if p.get("dtype") == "enum"]


def template_text(blk):
    """make: and callbacks of the Python template, where a parameter's value is used."""
    t = blk["templates"]
    return "\n".join([t["make"]] + list(t.get("callbacks", [])))


class qa_grc_options(gr_unittest.TestCase):

    def setUp(self):
        self.blocks = load_blocks()

    def test_every_block_definition_loaded(self):
        # the 19 C++ blocks of the module (docs/architecture.md), the imaging_chain hier
        # block, image_sink's Python GeoTIFF writer and the split chain's uav_link and
        # ground_link, one .block.yml each
        self.assertEqual(len(self.blocks), 23)
        self.assertTrue(all(k.startswith("nrsar_") for k in self.blocks))

    def test_builders_map_each_name_to_its_member(self):
        # params.py's tables are the bindings' enums by name, nothing added or missing
        for builder, names in ACCEPTED.items():
            make = getattr(nrsar, builder)
            if builder == "make_navigation":  # the name is its second argument
                geo = nrsar.make_geometry("short")
                truth = nrsar.make_trajectory("ideal", geo, duration_s=geo.aperture_s)
                for name in names:
                    make(truth, name, duration_s=geo.aperture_s, geo=geo)
                with self.assertRaises(ValueError, msg=builder):
                    make(truth, "no_such_name", duration_s=geo.aperture_s, geo=geo)
                continue
            for name in names:
                value = make(name) if builder != "make_beam" else make(name).mode
                if hasattr(value, "name"):
                    self.assertEqual(value.name.lower(), name, builder)
            with self.assertRaises(ValueError, msg=builder):
                make("no_such_name")

    def test_enum_options_are_the_accepted_names(self):
        checked = 0
        for bid, blk in self.blocks.items():
            if bid == "nrsar_imaging_chain":
                continue  # its options are SimOptions' fields: test_imaging_chain_is_sim_options
            text = template_text(blk)
            builders = {p: b for b, p in BUILDER.findall(text)}
            builders.update({p: KEYWORD_BUILDERS[k] for k, p in KEYWORD.findall(text)
                             if k in KEYWORD_BUILDERS})
            extras = {}
            for p, literal in LITERAL.findall(text):
                extras.setdefault(p, set()).add(literal)
            for p in enum_params(blk):
                where = f"{bid}.{p['id']}"
                options = [str(o) for o in p["options"]]
                self.assertEqual(len(options), len(set(options)), f"{where}: repeated option")
                self.assertEqual(len(p.get("option_labels", [])), len(options),
                                 f"{where}: one label per option")
                self.assertIn(str(p["default"]), options, f"{where}: default")
                if p["id"] not in builders:
                    # not handed to a builder: a Python literal in the template
                    self.assertEqual(set(options), {"True", "False"},
                                     f"{where}: options neither a builder's names nor booleans")
                    checked += 1
                    continue
                accepted = ACCEPTED[builders[p["id"]]]
                own = extras.get(p["id"], set())
                self.assertEqual(set(options) - own - set(accepted), set(),
                                 f"{where}: options {builders[p['id']]} does not accept")
                left_out = [n for n in accepted if n not in options]
                if left_out:
                    build = NARROWED.get((bid, p["id"]))
                    self.assertIsNotNone(build, f"{where}: {left_out} missing from the options")
                    for name in left_out:
                        with self.assertRaises(ValueError, msg=f"{where}: {name}"):
                            build(name)
                    build(str(p["default"]))  # the narrowing is the block's, not any name's
                checked += 1
        # enum parameters of the 15 blocks today; a new one is checked the same way
        self.assertGreaterEqual(checked, 37)

    def test_imaging_chain_is_sim_options(self):
        # generated from the options object (grc/gen_imaging_chain.py): every enum parameter
        # offers exactly the choices the command line accepts, which come from the bindings
        import dataclasses
        from gnuradio.nrsar.options import SimOptions
        fields = {f.name: f for f in dataclasses.fields(SimOptions)}
        for p in enum_params(self.blocks["nrsar_imaging_chain"]):
            self.assertEqual([str(o) for o in p["options"]],
                             [str(c) for c in fields[p["id"]].metadata["choices"]], p["id"])
        self.assertEqual(fields["filter"].metadata["choices"], sorted(nrsar.params.FILTERS))
        self.assertEqual(fields["preset"].metadata["choices"],
                         list(nrsar.numerology.preset_names()))

    def test_examples_use_valid_options(self):
        graphs = sorted(glob.glob(os.path.join(ROOT, "examples", "*.grc")))
        self.assertGreater(len(graphs), 0)
        for path in graphs:
            with open(path) as f:
                graph = yaml.safe_load(f)
            name = os.path.basename(path)
            for b in graph["blocks"]:
                if not b["id"].startswith("nrsar_"):
                    continue
                where = f"{name}: {b['name']} ({b['id']})"
                self.assertIn(b["id"], self.blocks, f"{where}: no such block in grc/")
                blk = self.blocks[b["id"]]
                defined = {p["id"] for p in blk["parameters"]}
                self.assertEqual(set(b["parameters"]) - defined - GRC_COMMON, set(),
                                 f"{where}: parameters the block does not have")
                for p in enum_params(blk):
                    value = b["parameters"].get(p["id"], p["default"])
                    self.assertIn(str(value), [str(o) for o in p["options"]],
                                  f"{where}.{p['id']}")

    def test_echo_blocks_fly_the_lever_arm(self):
        # The echo blocks' flight path as their make: template builds it, rendered with a CSV
        # path of constant yaw psi and a lever arm l: the phase centre is the navigated
        # point plus Rz(psi) l (attitude_matrix with roll = pitch = 0, docs/flight.md); the
        # straight line and the models refuse a lever arm.
        import math
        import tempfile
        psi, arm = 0.3, (0.5, 0.2, -0.1)
        path = os.path.join(tempfile.mkdtemp(prefix="qa_grc_lever_"), "yaw.csv")
        with open(path, "w") as f:
            f.write("t_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad\n")
            for i in range(16):
                f.write(f"{i / 50!r},0.0,{i!r},1000.0,0.0,0.0,{psi!r}\n")
        expected = (arm[0] * math.cos(psi) - arm[1] * math.sin(psi),
                    50 * 0.1 + arm[0] * math.sin(psi) + arm[1] * math.cos(psi), 1000.0 + arm[2])
        for bid in ("nrsar_scene_echo", "nrsar_td_echo", "nrsar_extended_scene_echo"):
            blk = self.blocks[bid]
            lever = [p for p in blk["parameters"] if p["id"] == "lever_arm"]
            self.assertEqual(len(lever), 1, bid)
            make = blk["templates"]["make"]
            start = make.index("nrsar.make_trajectory(")
            depth, end = 0, start
            for end in range(start, len(make)):
                depth += {"(": 1, ")": -1}.get(make[end], 0)
                if depth == 0 and make[end] == ")":
                    break
            values = {"trajectory": repr(path), "geometry": "short", "motion_seed": "0",
                      "lever_arm": repr(list(arm))}
            call = re.sub(r"\$\{(\w+)\}", lambda m: values[m.group(1)], make[start:end + 1])
            got = eval(call, {"nrsar": nrsar}).position(0.1)
            for a, b in zip(got, expected):
                self.assertAlmostEqual(a, b, places=9, msg=bid)
            values["trajectory"] = repr("gusty")
            with self.assertRaisesRegex(ValueError, "lever_arm_m = .* needs a CSV file"):
                eval(re.sub(r"\$\{(\w+)\}", lambda m: values[m.group(1)],
                            make[start:end + 1]), {"nrsar": nrsar})


if __name__ == "__main__":
    gr_unittest.run(qa_grc_options)
