/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 *
 */

/***********************************************************************************/
/* This file is hand-written (no block header): the NR channel-coding kernels of    */
/* TS 38.212 / 38.214 as functions on numpy arrays.                                 */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                        */
/* BINDTOOL_USE_PYGCCXML(0)                                                         */
/* BINDTOOL_HEADER_FILE(kernel/nr_ldpc.h)                                           */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                     */
/***********************************************************************************/

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <gnuradio/nrsar/kernel/nr_crc.h>
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <gnuradio/nrsar/kernel/nr_ldpc_decoder.h>
#include <gnuradio/nrsar/kernel/nr_rate_match.h>
#include <gnuradio/nrsar/kernel/nr_segmentation.h>
#include <gnuradio/nrsar/kernel/nr_tbs.h>
#include <gnuradio/nrsar/kernel/nr_ulsch.h>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

using namespace gr::nrsar::kernel;

namespace {

using bits_in = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;
using llr_in = py::array_t<float, py::array::c_style | py::array::forcecast>;

[[noreturn]] void fail(const std::string& name, const std::string& value, const std::string& limit)
{
    throw std::invalid_argument(name + " = " + value + " " + limit);
}

// 0/1 bits of a 1-D array (a filler -1 is allowed where allow_filler).
std::vector<std::uint8_t> to_bits(const bits_in& a, const char* name, bool allow_filler, std::vector<bool>* filler = nullptr)
{
    std::vector<std::uint8_t> b(a.size());
    const std::int64_t* p = a.data();
    if (filler)
        filler->assign(a.size(), false);
    for (py::ssize_t k = 0; k < a.size(); k++) {
        if (p[k] == 0 || p[k] == 1)
            b[k] = static_cast<std::uint8_t>(p[k]);
        else if (allow_filler && p[k] == -1) {
            b[k] = 0;
            if (filler)
                (*filler)[k] = true;
        } else
            fail(name, "[... " + std::to_string(p[k]) + " at index " + std::to_string(k) + " ...]",
                 allow_filler ? "must hold 0, 1 or -1 (filler)" : "must hold 0 or 1");
    }
    return b;
}

// Zc of a length that is cols Zc for the graph (K: 22 / 10, N: 66 / 50).
unsigned lifting_of(std::size_t len, unsigned per_zc, const char* what)
{
    if (len % per_zc != 0 || nr_lifting_set_index(static_cast<unsigned>(len / per_zc)) < 0)
        fail(what, std::to_string(len), "must be " + std::to_string(per_zc) + " Zc for a lifting size Zc of TS 38.212 Table 5.3.2-1");
    return static_cast<unsigned>(len / per_zc);
}

// Rows of a 1-D (one row) or 2-D array.
std::pair<std::size_t, std::size_t> rows_cols(const py::buffer_info& info, const char* name)
{
    if (info.ndim == 1)
        return { 1, static_cast<std::size_t>(info.shape[0]) };
    if (info.ndim == 2)
        return { static_cast<std::size_t>(info.shape[0]), static_cast<std::size_t>(info.shape[1]) };
    fail(name, std::to_string(info.ndim) + "-D array", "must be 1-D or 2-D");
}

nr_rate_match_params rm_params(int base_graph, unsigned zc, unsigned k_prime, unsigned rv, unsigned qm, std::optional<std::size_t> n_ref)
{
    nr_rate_match_params p;
    p.base_graph = base_graph;
    p.zc = zc;
    p.k_prime = k_prime;
    p.rv = rv;
    p.qm = qm;
    p.n_ref = n_ref.value_or(0);
    if (n_ref && *n_ref == 0)
        fail("n_ref", "0", "must be None (no limited-buffer rate matching) or > 0");
    p.validate();
    return p;
}

py::dict seg_dict(const nr_segmentation& s)
{
    py::dict d;
    d["base_graph"] = s.base_graph;
    d["B"] = s.B;
    d["C"] = s.C;
    d["L"] = s.L;
    d["K_prime"] = s.K_prime;
    d["Kb"] = s.Kb;
    d["Zc"] = s.Zc;
    d["K"] = s.K;
    d["F"] = s.F;
    return d;
}

} // namespace

void bind_nr_coding(py::module& m)
{
    m.def(
        "crc_attach",
        [](const bits_in& bits, const std::string& poly) {
            const nr_crc crc(nr_crc::parse(poly));
            const auto b = to_bits(bits, "bits", false);
            py::array_t<std::uint8_t> out(b.size() + crc.length());
            crc.attach(b.data(), b.size(), out.mutable_data());
            return out;
        },
        py::arg("bits"),
        py::arg("poly"),
        "TS 38.212 5.1: bits (0/1, a_0 first) followed by the L parity bits p_0 .. p_{L-1} of "
        "poly \"24A\", \"24B\" or \"16\" (uint8 array of len(bits) + L).");
    m.def(
        "crc_check",
        [](const bits_in& bits, const std::string& poly) {
            const auto b = to_bits(bits, "bits", false);
            return nr_crc(nr_crc::parse(poly)).check(b.data(), b.size());
        },
        py::arg("bits"),
        py::arg("poly"),
        "True when bits (data followed by its parity bits) divide by the generator polynomial.");
    m.def("select_base_graph", &nr_select_base_graph, py::arg("tbs"), py::arg("code_rate"),
          "TS 38.212 6.2.2: LDPC base graph (1 or 2) of a transport block of tbs bits at code rate R.");
    m.def("tb_crc_length", &nr_tb_crc_length, py::arg("tbs"),
          "TS 38.212 6.2.1: 24 (CRC24A) for tbs > 3824, else 16 (CRC16).");
    m.def(
        "segment_sizes",
        [](std::size_t n_bits, int base_graph) { return seg_dict(nr_segmentation::compute(n_bits, base_graph)); },
        py::arg("n_bits"),
        py::arg("base_graph"),
        "TS 38.212 5.2.2 sizes for B = n_bits (TB with CRC): dict with base_graph, B, C, L, "
        "K_prime, Kb, Zc, K, F.");
    m.def(
        "segment",
        [](const bits_in& bits, int base_graph) {
            const auto b = to_bits(bits, "bits", false);
            const auto s = nr_segmentation::compute(b.size(), base_graph);
            std::vector<std::uint8_t> cb(std::size_t{ s.C } * s.K);
            nr_segment(b.data(), s, cb.data(), 0xff);
            py::array_t<std::int8_t> out({ static_cast<py::ssize_t>(s.C), static_cast<py::ssize_t>(s.K) });
            std::int8_t* o = out.mutable_data();
            for (std::size_t k = 0; k < cb.size(); k++)
                o[k] = cb[k] == 0xff ? -1 : static_cast<std::int8_t>(cb[k]);
            return out;
        },
        py::arg("bits"),
        py::arg("base_graph"),
        "TS 38.212 5.2.2: bits b (TB with its CRC) into a C x K int8 array of code blocks: "
        "K' - L bits of b, CRC24B when C > 1, fillers as -1.");
    m.def(
        "desegment",
        [](const bits_in& code_blocks, std::size_t n_bits, int base_graph) {
            const auto s = nr_segmentation::compute(n_bits, base_graph);
            const auto [rows, cols] = rows_cols(code_blocks.request(), "code_blocks");
            if (rows != s.C || cols != s.K)
                fail("code_blocks", std::to_string(rows) + " x " + std::to_string(cols),
                     "must be C x K = " + std::to_string(s.C) + " x " + std::to_string(s.K));
            const auto cb = to_bits(code_blocks, "code_blocks", true);
            py::array_t<std::uint8_t> out(n_bits);
            const auto ok = std::make_unique<bool[]>(s.C);
            nr_desegment(cb.data(), s, out.mutable_data(), ok.get());
            py::array_t<bool> okv(s.C);
            for (unsigned r = 0; r < s.C; r++)
                okv.mutable_data()[r] = ok[r];
            return py::make_tuple(out, okv);
        },
        py::arg("code_blocks"),
        py::arg("n_bits"),
        py::arg("base_graph"),
        "Inverse of segment: (bits of the TB with its CRC, CRC24B ok per block; True when C = 1).");
    m.def(
        "ldpc_encode",
        [](const bits_in& code_blocks, int base_graph) {
            const nr_base_graph& g = nr_base_graph::get(base_graph);
            const auto [rows, K] = rows_cols(code_blocks.request(), "code_blocks");
            const unsigned zc = lifting_of(K, g.info_cols, "K (code block length)");
            std::vector<bool> filler;
            const auto c = to_bits(code_blocks, "code_blocks", true, &filler);
            nr_ldpc_encoder enc(base_graph, zc);
            const std::size_t N = enc.n();
            py::array_t<std::int8_t> out({ static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(N) });
            std::vector<std::uint8_t> d(N);
            std::int8_t* o = out.mutable_data();
            for (std::size_t r = 0; r < rows; r++) {
                enc.encode(c.data() + r * K, d.data());
                for (std::size_t k = 0; k < N; k++) {
                    const std::size_t src = k + 2 * zc; // d_{k} = c_{k + 2Zc} for k < K - 2Zc
                    o[r * N + k] = (src < K && filler[r * K + src]) ? -1 : static_cast<std::int8_t>(d[k]);
                }
            }
            if (code_blocks.ndim() == 1)
                return out.attr("reshape")(N).cast<py::array_t<std::int8_t>>();
            return out;
        },
        py::arg("code_blocks"),
        py::arg("base_graph"),
        "TS 38.212 5.3.2: code blocks (1-D K or 2-D C x K, fillers -1) -> codewords d of N = 66 Zc "
        "(BG1) / 50 Zc (BG2) bits (the 2 Zc first systematic bits punctured), fillers -1.");
    m.def(
        "rate_match",
        [](const bits_in& codeword, std::size_t e, unsigned rv, unsigned qm, int base_graph, std::optional<std::size_t> n_ref) {
            const nr_base_graph& g = nr_base_graph::get(base_graph);
            if (codeword.ndim() != 1)
                fail("codeword", std::to_string(codeword.ndim()) + "-D array", "must be 1-D");
            const unsigned zc = lifting_of(codeword.size(), g.cols - 2, "len(codeword)");
            std::vector<bool> filler;
            const auto d = to_bits(codeword, "codeword", true, &filler);
            const std::size_t K = nr_ldpc_k(base_graph, zc);
            std::size_t n_fill = 0;
            for (bool f : filler)
                n_fill += f;
            const auto p = rm_params(base_graph, zc, static_cast<unsigned>(K - n_fill), rv, qm, n_ref);
            for (std::size_t k = 0; k < filler.size(); k++)
                if (filler[k] != (k >= p.filler_begin() && k < p.filler_end()))
                    fail("codeword", "[... -1 at index " + std::to_string(k) + " ...]",
                         "must hold its fillers (-1) at d_{K'-2Zc} .. d_{K-2Zc-1} only");
            py::array_t<std::uint8_t> out(e);
            nr_rate_match(d.data(), p, e, out.mutable_data());
            return out;
        },
        py::arg("codeword"),
        py::arg("e"),
        py::arg("rv"),
        py::arg("qm"),
        py::arg("base_graph"),
        py::arg("n_ref") = py::none(),
        "TS 38.212 5.4.2: E = e bits f from codeword d (fillers -1, skipped): circular buffer "
        "N_cb = N or min(N, n_ref), start k0 of rv (Table 5.4.2.1-2), bit interleaving by qm.");
    m.def(
        "rate_recover",
        [](const llr_in& llrs, int base_graph, unsigned zc, unsigned k_prime, unsigned rv, unsigned qm,
           std::optional<std::size_t> n_ref, std::optional<llr_in> buffer) {
            if (llrs.ndim() != 1)
                fail("llrs", std::to_string(llrs.ndim()) + "-D array", "must be 1-D");
            const auto p = rm_params(base_graph, zc, k_prime, rv, qm, n_ref);
            const std::size_t N = p.n();
            py::array_t<float> out(N);
            float* o = out.mutable_data();
            if (buffer) {
                if (buffer->ndim() != 1 || static_cast<std::size_t>(buffer->size()) != N)
                    fail("buffer", "of size " + std::to_string(buffer->size()), "must be 1-D of N = " + std::to_string(N));
                std::copy(buffer->data(), buffer->data() + N, o);
            }
            nr_rate_recover(llrs.data(), p, llrs.size(), o, buffer.has_value());
            return out;
        },
        py::arg("llrs"),
        py::arg("base_graph"),
        py::arg("zc"),
        py::arg("k_prime"),
        py::arg("rv"),
        py::arg("qm"),
        py::arg("n_ref") = py::none(),
        py::arg("buffer") = py::none(),
        "Inverse of rate_match on LLRs (positive = bit 0): N float32 soft values of d, the E LLRs "
        "added at the positions they were read from, to buffer (a previous transmission: HARQ "
        "combining) or to zeros; fillers +inf (known 0).");
    m.def("code_block_e", &nr_code_block_e, py::arg("g"), py::arg("c"), py::arg("qm"), py::arg("n_layers") = 1,
          "TS 38.212 5.4.2.1: rate-matched length E_r of each of the C code blocks of G coded bits.");
    m.def(
        "ldpc_decode",
        [](const llr_in& llrs, int base_graph, unsigned max_iter) {
            if (max_iter < 1)
                fail("max_iter", std::to_string(max_iter), "must be at least 1");
            const nr_base_graph& g = nr_base_graph::get(base_graph);
            const auto [rows, N] = rows_cols(llrs.request(), "llrs");
            const unsigned zc = lifting_of(N, g.cols - 2, "N (codeword length)");
            nr_ldpc_decoder dec(base_graph, zc, max_iter);
            const std::size_t K = dec.k();
            py::array_t<std::uint8_t> bits({ static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(K) });
            py::array_t<unsigned> iters(rows);
            py::array_t<bool> ok(rows);
            for (std::size_t r = 0; r < rows; r++) {
                const auto res = dec.decode(llrs.data() + r * N, bits.mutable_data() + r * K);
                iters.mutable_data()[r] = res.iterations;
                ok.mutable_data()[r] = res.parity_ok;
            }
            if (llrs.ndim() == 1)
                return py::make_tuple(bits.attr("reshape")(K), iters.attr("item")(0), ok.attr("item")(0));
            return py::make_tuple(bits, iters, ok);
        },
        py::arg("llrs"),
        py::arg("base_graph"),
        py::arg("max_iter") = 8,
        "Layered offset min-sum (int8, AVX2; offset 0.5 in LLR units) decoding of N LLRs of d (1-D, or 2-D C x N; "
        "positive = bit 0, 0 = punctured, +inf = filler). Returns (bits c of K = 22 Zc / 10 Zc, "
        "fillers 0; iterations; parity_ok), per row for 2-D input.");
    m.def(
        "tbs",
        [](const std::string& mcs_table, unsigned mcs, unsigned n_prb, unsigned n_symbols, unsigned n_dmrs_re_per_prb,
           unsigned n_layers, unsigned n_oh) {
            return nr_tbs(nr_parse_mcs_table(mcs_table), mcs, n_prb, n_symbols, n_dmrs_re_per_prb, n_layers, n_oh);
        },
        py::arg("mcs_table"),
        py::arg("mcs"),
        py::arg("n_prb"),
        py::arg("n_symbols"),
        py::arg("n_dmrs_re_per_prb"),
        py::arg("n_layers") = 1,
        py::arg("n_oh") = 0,
        "TS 38.214 5.1.3.2 transport block size; mcs_table \"qam64\" (Table 5.1.3.1-1) or \"qam256\" (5.1.3.1-2).");
    m.def(
        "mcs",
        [](const std::string& mcs_table, unsigned mcs) {
            const auto e = nr_mcs(nr_parse_mcs_table(mcs_table), mcs);
            return py::make_tuple(e.qm, e.code_rate());
        },
        py::arg("mcs_table"),
        py::arg("mcs"),
        "Row of a TS 38.214 MCS table: (Qm, target code rate R).");
    m.def("scrambling_c_init", &nr_scrambling_c_init, py::arg("n_rnti"), py::arg("n_id"),
          "TS 38.211 6.3.1.1: c_init = n_RNTI 2^15 + n_ID.");
    m.def(
        "scrambling_sequence",
        [](std::uint32_t c_init, std::size_t n) {
            gold_sequence c(c_init);
            py::array_t<std::uint8_t> out(n);
            c.generate_unpacked(out.mutable_data(), n);
            return out;
        },
        py::arg("c_init"),
        py::arg("n"),
        "TS 38.211 5.2.1 sequence c(0) .. c(n-1) (uint8 0/1) for c_init (31 bits).");
    m.def(
        "ldpc_base_graph",
        [](int base_graph) {
            const nr_base_graph& g = nr_base_graph::get(base_graph);
            py::array_t<int> out({ static_cast<py::ssize_t>(g.n_entries), py::ssize_t{ 10 } });
            int* o = out.mutable_data();
            for (std::size_t k = 0; k < g.n_entries; k++) {
                o[10 * k] = g.entries[k].i;
                o[10 * k + 1] = g.entries[k].j;
                for (int s = 0; s < 8; s++)
                    o[10 * k + 2 + s] = g.entries[k].v[s];
            }
            return out;
        },
        py::arg("base_graph"),
        "TS 38.212 Table 5.3.2-2 (1) / 5.3.2-3 (2): one row per non-zero entry: i, j, V_ij for iLS 0..7.");
    py::class_<nr_ulsch>(m, "ulsch",
                         "UL-SCH of TS 38.212 6.2 for one TB (CRC, base graph, segmentation, LDPC, rate "
                         "matching, concatenation) with the 38.211 6.3.1.1 scrambling and HARQ soft buffers.")
        .def(py::init([](std::size_t tbs, double code_rate, unsigned qm, std::size_t g, unsigned n_layers,
                         std::optional<std::size_t> n_ref, unsigned max_iter) {
                 if (max_iter < 1)
                     fail("max_iter", std::to_string(max_iter), "must be at least 1");
                 if (n_ref && *n_ref == 0)
                     fail("n_ref", "0", "must be None (no limited-buffer rate matching) or > 0");
                 return std::make_unique<nr_ulsch>(tbs, code_rate, qm, g, n_layers, n_ref.value_or(0), max_iter);
             }),
             py::arg("tbs"),
             py::arg("code_rate"),
             py::arg("qm"),
             py::arg("g"),
             py::arg("n_layers") = 1,
             py::arg("n_ref") = py::none(),
             py::arg("max_iter") = 8)
        .def_property_readonly("base_graph", &nr_ulsch::base_graph)
        .def_property_readonly("e", &nr_ulsch::e)
        .def_property_readonly("effective_rate", &nr_ulsch::effective_rate)
        .def_property_readonly("segmentation", [](const nr_ulsch& u) { return seg_dict(u.segmentation()); })
        .def(
            "encode",
            [](nr_ulsch& u, const bits_in& bits, unsigned rv, std::uint32_t c_init) {
                if (static_cast<std::size_t>(bits.size()) != u.tbs())
                    fail("bits", "of length " + std::to_string(bits.size()), "must hold tbs = " + std::to_string(u.tbs()) + " bits");
                const auto a = to_bits(bits, "bits", false);
                py::array_t<std::uint8_t> out(u.g());
                u.encode(a.data(), rv, c_init, out.mutable_data());
                return out;
            },
            py::arg("bits"),
            py::arg("rv"),
            py::arg("c_init"),
            "tbs bits -> G scrambled coded bits (uint8) of redundancy version rv.")
        .def(
            "decode",
            [](nr_ulsch& u, const llr_in& llrs, unsigned rv, std::uint32_t c_init, bool combine) {
                if (static_cast<std::size_t>(llrs.size()) != u.g())
                    fail("llrs", "of length " + std::to_string(llrs.size()), "must hold G = " + std::to_string(u.g()) + " LLRs");
                py::array_t<std::uint8_t> out(u.tbs());
                const auto r = u.decode(llrs.data(), rv, c_init, combine, out.mutable_data());
                py::dict d;
                d["tb_crc_ok"] = r.tb_crc_ok;
                d["parity_ok"] = r.parity_ok;
                d["cb_crc_ok"] = r.cb_crc_ok;
                d["code_blocks"] = r.code_blocks;
                d["mean_iterations"] = r.mean_iterations;
                return py::make_tuple(out, d);
            },
            py::arg("llrs"),
            py::arg("rv"),
            py::arg("c_init"),
            py::arg("combine") = false,
            "G LLRs (positive = bit 0, scrambled) -> (tbs bits, dict tb_crc_ok, parity_ok, cb_crc_ok, "
            "code_blocks, mean_iterations); combine=True adds to the previous transmissions (HARQ). "
            "An all-zero output passes the CRC: parity_ok tells a real decode from no information.");
    m.def("lifting_set_index", &nr_lifting_set_index, py::arg("zc"),
          "Set index iLS of Zc (TS 38.212 Table 5.3.2-1), -1 when zc is not a lifting size.");
}
