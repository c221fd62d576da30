#!/usr/bin/python3
"""An independent reference for the HMM engine (engine/hmm), written from the textbook formulas in numpy.

Not part of the product: the cross-check test (tests/hmm/reference_check_test.cpp) and the benchmark
(bench/hmm_bench.cpp) run it. It is deliberately *not* a port of the C++ code: densities use
numpy.linalg.slogdet/solve instead of a Cholesky factor, the forward-backward recursions run in the log domain
(log-sum-exp over predecessors) instead of per-frame scaling, and covariances are accumulated from centred data.

    /usr/bin/python3 tools/hmm_reference.py loglik MODEL.json DATA.csv [--seq]
    /usr/bin/python3 tools/hmm_reference.py bw-iteration MODEL.json DATA.csv [--repeat K] [-o NEW.json] [--json]
    /usr/bin/python3 tools/hmm_reference.py gmm-sklearn DATA.csv --components M --covariance full|diag -o GMM.json

MODEL.json is the talkinghead model file (format "talkinghead-hmm", version 1; engine/hmm/model_file.h).
DATA.csv has a header row and one frame per row; a column named `seq` (if present) splits the rows into
sequences (a new sequence starts wherever its value changes) and is not part of the observation. When the model
names its columns, those columns are taken from the CSV by name, in the model's order.

References: Rabiner (1989), "A tutorial on hidden Markov models...", eqs. 19-20 (forward), 24-25 (backward),
27 (gamma), 37 (xi), 40a-c (re-estimation of pi, A), 52-54 (mixture weights, means, covariances); Bishop (2006),
PRML eq. 2.43 (multivariate Gaussian) and 9.17 (mixture responsibilities).

Numbers: Debian's python3-numpy (and python3-sklearn for gmm-sklearn) only; call /usr/bin/python3 explicitly.
Timing runs are single-threaded when OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 are set in the environment (the
benchmark does that; `--threads 1` here sets them before numpy is imported).
"""

import argparse
import json
import math
import os
import sys
import time


def _set_threads_before_numpy(argv):
    """Honour --threads N before numpy (and its BLAS) is loaded: BLAS reads these variables only at start-up."""
    for i, arg in enumerate(argv):
        value = None
        if arg == "--threads" and i + 1 < len(argv):
            value = argv[i + 1]
        elif arg.startswith("--threads="):
            value = arg.split("=", 1)[1]
        if value is not None:
            for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS"):
                os.environ[name] = value


_set_threads_before_numpy(sys.argv)

import numpy as np  # noqa: E402  (after the thread settings on purpose)

LOG_2PI = math.log(2.0 * math.pi)


# ----------------------------------------------------------------------------------------------------------------
# Files


class Model:
    """pi (N), A (N x N, rows = from-state), per state: weights (M), means (M x d), covariances (M x d x d) for
    'full' or variances (M x d) for 'diagonal'."""

    def __init__(self, initial, transition, weights, means, covs, covariance, columns=None, blocks=None):
        self.initial = np.asarray(initial, dtype=float)
        self.transition = np.asarray(transition, dtype=float)
        self.weights = [np.asarray(w, dtype=float) for w in weights]
        self.means = [np.asarray(m, dtype=float) for m in means]
        self.covs = [np.asarray(c, dtype=float) for c in covs]
        self.covariance = covariance
        self.columns = list(columns or [])
        self.blocks = list(blocks or [])

    @property
    def num_states(self):
        return len(self.weights)

    @property
    def dimension(self):
        return self.means[0].shape[1]


def load_model(path):
    with open(path, encoding="utf-8") as f:
        doc = json.load(f)
    if doc.get("format") != "talkinghead-hmm":
        raise ValueError(f"{path}: not a talkinghead-hmm model (format = {doc.get('format')!r})")
    if doc.get("version") != 1:
        raise ValueError(f"{path}: unsupported version {doc.get('version')!r}")
    covariance = doc["covariance"]
    if covariance not in ("full", "diagonal"):
        raise ValueError(f"{path}: covariance must be 'full' or 'diagonal', not {covariance!r}")
    weights, means, covs = [], [], []
    for state in doc["states"]:
        weights.append(state["weights"])
        means.append([c["mean"] for c in state["components"]])
        if covariance == "full":
            covs.append([c["covariance"] for c in state["components"]])
        else:
            covs.append([c["variances"] for c in state["components"]])
    return Model(doc["initial"], doc["transition"], weights, means, covs, covariance, doc.get("columns"),
                 doc.get("blocks"))


def model_to_json(model, training):
    states = []
    for w, means, covs in zip(model.weights, model.means, model.covs):
        key = "covariance" if model.covariance == "full" else "variances"
        states.append({"weights": w.tolist(),
                       "components": [{"mean": m.tolist(), key: c.tolist()} for m, c in zip(means, covs)]})
    return {"format": "talkinghead-hmm", "version": 1, "covariance": model.covariance,
            "columns": model.columns, "blocks": model.blocks,
            "initial": model.initial.tolist(), "transition": model.transition.tolist(),
            "states": states, "training": training}


def save_json(path, doc):
    # json writes floats with repr(): the shortest text that reads back to the same double.
    with open(path, "w", encoding="utf-8") as f:
        json.dump(doc, f)
        f.write("\n")


def load_data(path, require_seq=False, columns=None):
    """Returns (list of T_k x d arrays, the observation column names)."""
    with open(path, encoding="utf-8") as f:
        header = [name.strip() for name in f.readline().strip().split(",")]
    values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if values.shape[1] != len(header):
        raise ValueError(f"{path}: {values.shape[1]} values per row but {len(header)} names in the header")
    if "seq" in header:
        seq = values[:, header.index("seq")]
        starts = np.flatnonzero(np.r_[True, seq[1:] != seq[:-1]])
    elif require_seq:
        raise ValueError(f"{path}: --seq given but there is no 'seq' column")
    else:
        starts = np.array([0])
    observed = [name for name in header if name != "seq"]
    if columns:
        missing = [name for name in columns if name not in header]
        if missing:
            raise ValueError(f"{path}: the model's columns {missing} are not in the data")
        observed = list(columns)
    frames = values[:, [header.index(name) for name in observed]]
    bounds = list(starts) + [len(frames)]
    return [frames[a:b] for a, b in zip(bounds[:-1], bounds[1:]) if b > a], observed


# ----------------------------------------------------------------------------------------------------------------
# Densities


def logsumexp(a, axis):
    """log sum exp(a) along `axis`, stable; -inf where every term is -inf."""
    peak = np.max(a, axis=axis, keepdims=True)
    peak = np.where(np.isfinite(peak), peak, 0.0)
    with np.errstate(divide="ignore"):
        out = np.log(np.sum(np.exp(a - peak), axis=axis, keepdims=True)) + peak
    return np.squeeze(out, axis=axis)


def log_gaussian_full(x, mean, cov):
    """log N(x; mu, Sigma) for every row of x (T x d): -1/2 (d log 2 pi + log|Sigma| + (x-mu)' Sigma^-1 (x-mu))."""
    sign, logdet = np.linalg.slogdet(cov)
    if sign <= 0:
        raise ValueError("covariance is not positive definite")
    diff = x - mean
    mahalanobis = np.sum(diff.T * np.linalg.solve(cov, diff.T), axis=0)
    return -0.5 * (x.shape[1] * LOG_2PI + logdet + mahalanobis)


def log_gaussian_diagonal(x, mean, variances):
    """The same with Sigma = diag(variances): -1/2 sum_k (log 2 pi sigma_k^2 + (x_k - mu_k)^2 / sigma_k^2)."""
    return -0.5 * (np.sum(np.log(2.0 * math.pi * variances)) + np.sum((x - mean) ** 2 / variances, axis=1))


def component_log_terms(model, state, x):
    """log w_m + log N_m(x_t) for the components of one state (M x T)."""
    density = log_gaussian_full if model.covariance == "full" else log_gaussian_diagonal
    with np.errstate(divide="ignore"):
        log_w = np.log(model.weights[state])
    rows = []
    for m in range(len(log_w)):
        rows.append(np.full(len(x), -np.inf) if log_w[m] == -np.inf
                    else log_w[m] + density(x, model.means[state][m], model.covs[state][m]))
    return np.array(rows)


def emission_log_likelihoods(model, x):
    """log b_j(x_t) (T x N) and the per-state component terms (list of M x T)."""
    terms = [component_log_terms(model, j, x) for j in range(model.num_states)]
    return np.stack([logsumexp(t, axis=0) for t in terms], axis=1), terms


# ----------------------------------------------------------------------------------------------------------------
# Forward-backward in the log domain


def log_params(model):
    with np.errstate(divide="ignore"):
        return np.log(model.initial), np.log(model.transition)


def forward(log_pi, log_a, log_b):
    """log alpha (T x N): alpha_1 = pi b(x_1); alpha_t(j) = [sum_i alpha_{t-1}(i) a_ij] b_j(x_t)."""
    num_frames, num_states = log_b.shape
    log_alpha = np.empty((num_frames, num_states))
    log_alpha[0] = log_pi + log_b[0]
    for t in range(1, num_frames):
        log_alpha[t] = logsumexp(log_alpha[t - 1][:, None] + log_a, axis=0) + log_b[t]
    return log_alpha


def backward(log_a, log_b):
    """log beta (T x N): beta_T = 1; beta_t(i) = sum_j a_ij b_j(x_{t+1}) beta_{t+1}(j)."""
    num_frames, num_states = log_b.shape
    log_beta = np.empty((num_frames, num_states))
    log_beta[-1] = 0.0
    for t in range(num_frames - 2, -1, -1):
        log_beta[t] = logsumexp(log_a + (log_b[t + 1] + log_beta[t + 1])[None, :], axis=1)
    return log_beta


def log_likelihood(model, sequences):
    log_pi, log_a = log_params(model)
    total = 0.0
    for x in sequences:
        log_b, _ = emission_log_likelihoods(model, x)
        total += float(logsumexp(forward(log_pi, log_a, log_b)[-1], axis=0))
    return total


def baum_welch_iteration(model, sequences, xi_chunk=4096):
    """One maximum-likelihood EM iteration; returns (new model, log P(X | old model))."""
    num_states, dim = model.num_states, model.dimension
    log_pi, log_a = log_params(model)
    pi_counts = np.zeros(num_states)
    xi_counts = np.zeros((num_states, num_states))
    # Per state and component: sum gamma, and the data with their per-frame responsibilities, kept for the
    # centred second moment after the means are known.
    gammas = [[] for _ in range(num_states)]  # per state: list over sequences of (M x T_k)
    total = 0.0
    for x in sequences:
        log_b, terms = emission_log_likelihoods(model, x)
        log_alpha = forward(log_pi, log_a, log_b)
        log_beta = backward(log_a, log_b)
        log_px = float(logsumexp(log_alpha[-1], axis=0))
        total += log_px
        log_gamma = log_alpha + log_beta - log_px                                   # Rabiner eq. 27
        pi_counts += np.exp(log_gamma[0])
        # xi_t(i, j) = alpha_t(i) a_ij b_j(x_{t+1}) beta_{t+1}(j) / P(X)            # Rabiner eq. 37
        after = log_b[1:] + log_beta[1:]
        for a in range(0, len(x) - 1, xi_chunk):
            b = min(a + xi_chunk, len(x) - 1)
            log_xi = log_alpha[a:b, :, None] + log_a[None, :, :] + after[a:b, None, :] - log_px
            xi_counts += np.exp(log_xi).sum(axis=0)
        for j in range(num_states):
            # gamma_t(j, m) = gamma_t(j) w_m N_m(x_t) / b_j(x_t)                    # Rabiner eq. 54
            gammas[j].append(np.exp(log_gamma[:, j][None, :] + terms[j] - log_b[:, j][None, :]))

    initial = pi_counts / pi_counts.sum()                                           # eq. 40a
    with np.errstate(invalid="ignore"):
        transition = xi_counts / xi_counts.sum(axis=1, keepdims=True)               # eq. 40b
    transition = np.where(np.isfinite(transition), transition, model.transition)
    frames = np.concatenate(sequences, axis=0)
    weights, means, covs = [], [], []
    for j in range(num_states):
        g = np.concatenate(gammas[j], axis=1)  # M x T
        occupancy = g.sum(axis=1)
        weights.append(occupancy / occupancy.sum() if occupancy.sum() > 0 else model.weights[j])  # eq. 52
        state_means, state_covs = [], []
        for m in range(g.shape[0]):
            if occupancy[m] <= 0.0:
                state_means.append(model.means[j][m])
                state_covs.append(model.covs[j][m])
                continue
            mean = g[m] @ frames / occupancy[m]                                     # eq. 53
            diff = frames - mean
            if model.covariance == "full":
                cov = (diff * g[m][:, None]).T @ diff / occupancy[m]                # eq. 54
            else:
                cov = g[m] @ (diff * diff) / occupancy[m]
            state_means.append(mean)
            state_covs.append(cov)
        means.append(np.array(state_means))
        covs.append(np.array(state_covs))
    new = Model(initial, transition, weights, means, covs, model.covariance, model.columns, model.blocks)
    return new, total


# ----------------------------------------------------------------------------------------------------------------
# Commands


def command_loglik(args):
    model = load_model(args.model)
    sequences, _ = load_data(args.data, args.seq, model.columns)
    check_dimension(model, sequences, args.data)
    print(repr(log_likelihood(model, sequences)))


def loaded_linear_algebra_libraries():
    """The BLAS/LAPACK shared libraries numpy actually loaded (Debian: netlib or OpenBLAS, by alternatives)."""
    found = set()
    try:
        with open("/proc/self/maps", encoding="utf-8") as maps:
            for line in maps:
                path = line.split()[-1]
                name = os.path.basename(path)
                if path.startswith("/") and ("blas" in name or "lapack" in name):
                    found.add(os.path.realpath(path))
    except OSError:
        pass
    return sorted(found)


def command_bw_iteration(args):
    model = load_model(args.model)
    sequences, _ = load_data(args.data, args.seq, model.columns)
    check_dimension(model, sequences, args.data)
    cpu, wall = [], []
    for _ in range(args.repeat):
        cpu0, wall0 = time.process_time(), time.perf_counter()
        new, log_px = baum_welch_iteration(model, sequences)
        cpu.append(time.process_time() - cpu0)
        wall.append(time.perf_counter() - wall0)
    if args.output:
        save_json(args.output, model_to_json(new, {"tool": "hmm_reference.py bw-iteration",
                                                   "log_likelihood_before": log_px}))
    frames = sum(len(x) for x in sequences)
    if args.json:
        print(json.dumps({"cpu_seconds": cpu, "wall_seconds": wall, "log_likelihood": log_px, "frames": frames,
                          "blas_threads": os.environ.get("OPENBLAS_NUM_THREADS"),
                          "numpy": np.__version__, "blas": loaded_linear_algebra_libraries()}))
    else:
        print(f"{sum(cpu) / len(cpu):.6f} s per iteration (CPU; wall {sum(wall) / len(wall):.6f} s), "
              f"{args.repeat} run(s), {frames} frames, N={model.num_states}, d={model.dimension}; "
              f"log P(X) = {log_px!r}")


def command_gmm_sklearn(args):
    from sklearn.mixture import GaussianMixture  # python3-sklearn

    sequences, columns = load_data(args.data)
    frames = np.concatenate(sequences, axis=0)
    gmm = GaussianMixture(n_components=args.components, covariance_type=args.covariance, max_iter=args.iterations,
                          random_state=args.seed, reg_covar=args.reg_covar)
    gmm.fit(frames)
    score = float(np.sum(gmm.score_samples(frames)))
    covariance = "full" if args.covariance == "full" else "diagonal"
    model = Model([1.0], [[1.0]], [gmm.weights_], [gmm.means_], [gmm.covariances_], covariance, columns)
    if args.output:
        save_json(args.output, model_to_json(model, {"tool": "sklearn.mixture.GaussianMixture",
                                                     "score_samples_sum": score, "converged": bool(gmm.converged_),
                                                     "iterations": int(gmm.n_iter_)}))
    print(repr(score))


def check_dimension(model, sequences, path):
    if sequences and sequences[0].shape[1] != model.dimension:
        raise ValueError(f"{path}: {sequences[0].shape[1]} observation columns, the model has {model.dimension}")


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--threads", help="BLAS threads (read from the command line before numpy loads)")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("loglik", parents=[common], help="total log-likelihood of the data under the model")
    p.add_argument("model")
    p.add_argument("data")
    p.add_argument("--seq", action="store_true", help="require a 'seq' column (it splits sequences if present)")
    p.set_defaults(run=command_loglik)

    p = sub.add_parser("bw-iteration", parents=[common], help="one maximum-likelihood Baum-Welch iteration, timed")
    p.add_argument("model")
    p.add_argument("data")
    p.add_argument("--seq", action="store_true")
    p.add_argument("--repeat", type=int, default=1, help="run the same iteration K times (timing)")
    p.add_argument("-o", "--output", help="write the re-estimated model here")
    p.add_argument("--json", action="store_true", help="print the timings as one JSON object")
    p.set_defaults(run=command_bw_iteration)

    p = sub.add_parser("gmm-sklearn", parents=[common], help="fit sklearn's GaussianMixture; print its score_samples sum")
    p.add_argument("data")
    p.add_argument("--components", type=int, required=True)
    p.add_argument("--covariance", choices=["full", "diag"], required=True)
    p.add_argument("--iterations", type=int, default=200)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--reg-covar", type=float, default=1e-6)
    p.add_argument("-o", "--output", help="write the fitted mixture as a one-state talkinghead model")
    p.set_defaults(run=command_gmm_sklearn)

    args = parser.parse_args(argv)
    if getattr(args, "repeat", 1) < 1:
        parser.error("--repeat must be at least 1")
    try:
        args.run(args)
    except (OSError, ValueError, KeyError) as e:
        print(f"hmm_reference.py: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
