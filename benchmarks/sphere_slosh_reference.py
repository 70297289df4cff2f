"""The reference for the sphere's slosh modes by tank fraction: an independent axisymmetric
finite-element solution of linear slosh theory, converged to 8 digits.

    python benchmarks/sphere_slosh_reference.py [--fills 0.1 ... 0.9] [--levels 8 16 32 64]
                                                [--smoke]

No published table of lambda1 = omega^2 R / g by fill could be read on this machine
(Budiansky 1960 gives the half-full sphere, 1.5602; Chu 1962 and McIver 1989 tabulate others
behind paywalls), so the modes rung is checked against this: the m = 1 mixed Steklov problem
on the meridian section, Phi(r, z) cos(theta) with

    int (Phi_r Psi_r + Phi_z Psi_z + Phi Psi / r^2) r dr dz = lambda int_F Phi Psi r dr

(R = g = 1, Phi = 0 on the axis), isoparametric P2 triangles from scikit-fem on a
block-structured mesh mapped onto the exact circular wall, graded towards the contact line
(whose corner singularity otherwise lowers the order), the eigenproblem by ARPACK in
shift-invert. Per fill: lambda1 at each level and Richardson's value with the observed order
(about 4, P2's), lambda2, and the first slosh mass fraction
m1 / M = lambda1 (int_F x phi)^2 / (V int_F phi^2). Checks printed beside it: the upright
cylinder (a = h = 1) against lambda = xi tanh(xi h / a) (``cylinder``), and the half-full
sphere against Budiansky's 1.5602 (``budiansky_half``). A full run writes
``docs/data/sphere_slosh_reference.json``, which ``benchmarks/modes_by_fill.py`` and the
documentation read; ``--smoke``: tank fraction 0.5 on levels 4, 8, 16.
"""
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import brentq
from scipy.special import jnp_zeros

from skfem import Basis, ElementTriP2

from fluid.section.mesh import cylinder_section, flat_top, sphere_section
from fluid.section.potential import harmonic_form


def build_sphere_mesh(z0, n, grade=1.0):
    return sphere_section(flat_top(z0), n, grade), dict(a0=np.sqrt(1 - z0 ** 2), z0=z0)


def build_cylinder_mesh(h, n):
    return cylinder_section(h, n), dict(a0=1.0, z0=0.0)


# ----------------------------------------------------------------------------
# FEM
# ----------------------------------------------------------------------------

def surface_forms(mesh, fs, N, nq=8):
    """Isoparametric P2 trace integrals on the (straight) free surface facets:
    Ms_ij = int psi_i psi_j r dr,  b_i = int psi_i r^2 dr.  Done by hand
    (skfem's FacetBasis needs an inverse-map Newton solve that fails to meet
    its absolute 1e-12 tolerance on the finest meshes)."""
    Nv = mesh.nvertices
    f = mesh.facets[:, fs]
    dofs = np.vstack([f[0], Nv + fs, f[1]])          # end, edge node, end
    X = mesh.doflocs[:, dofs]                        # (2, 3, nf)
    t, w = np.polynomial.legendre.leggauss(nq)
    t = 0.5 * (t + 1)
    w = 0.5 * w
    Nf = np.array([(1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)])      # (3, nq)
    dN = np.array([4 * t - 3, 4 - 8 * t, 4 * t - 1])
    xq = np.einsum("dkf,kq->dfq", X, Nf)            # (2, nf, nq)
    dxq = np.einsum("dkf,kq->dfq", X, dN)
    J = np.sqrt(dxq[0] ** 2 + dxq[1] ** 2)            # (nf, nq)
    r = xq[0]
    wq = w[None, :] * J                               # (nf, nq)
    Mloc = np.einsum("iq,jq,fq->fij", Nf, Nf, wq * r)
    bloc = np.einsum("iq,fq->fi", Nf, wq * r ** 2)
    I = np.repeat(dofs.T[:, :, None], 3, axis=2)
    Jc = np.repeat(dofs.T[:, None, :], 3, axis=1)
    Ms = sp.coo_matrix((Mloc.ravel(), (I.ravel(), Jc.ravel())), shape=(N, N)).tocsr()
    b = np.bincount(dofs.T.ravel(), weights=bloc.ravel(), minlength=N)
    return Ms, b, wq.sum(), np.unique(dofs)


def solve(mesh, z0, a0, k=30, intorder=6):
    basis = Basis(mesh, ElementTriP2(), intorder=intorder)
    fs = mesh.facets_satisfying(lambda x: np.abs(x[1] - z0) < 1e-9, boundaries_only=True)
    fa = mesh.facets_satisfying(lambda x: np.abs(x[0]) < 1e-12, boundaries_only=True)
    K = harmonic_form(1).assemble(basis)
    Ms, b, slen, sdofs = surface_forms(mesh, fs, basis.N)
    D = basis.get_dofs(fa).flatten()
    I = np.setdiff1d(np.arange(basis.N), D)
    Kc = K[I][:, I].tocsc()
    Mc = Ms[I][:, I].tocsc()
    bc = b[I]
    nsurf = len(sdofs)
    k = min(k, nsurf - 3)
    lu = spla.splu(Kc, permc_spec="COLAMD")
    Kinv = spla.LinearOperator(Kc.shape, matvec=lu.solve, dtype=float)
    # M_s x = mu K x, mu = 1/lambda ; K SPD
    mu, X = spla.eigsh(Mc, k=k, M=Kc, Minv=Kinv, which="LA", tol=1e-13, maxiter=20000)
    order = np.argsort(-mu)
    mu, X = mu[order], X[:, order]
    lam = 1.0 / mu
    c = bc @ X                      # int Phi r^2 dr
    nn = np.einsum("ij,ij->j", X, Mc @ X)   # int Phi^2 r dr
    S = np.pi * c ** 2 / nn          # = (int_F x phi dA)^2 / int_F phi^2 dA
    return dict(lam=lam, S=S, ndof=len(I), nsurf=nsurf, slen=slen)


def richardson(vals, hs_ratio=2.0):
    v = np.asarray(vals, float)
    out = []
    for i in range(2, len(v)):
        d1, d2 = v[i - 1] - v[i - 2], v[i] - v[i - 1]
        if d2 == 0 or d1 / d2 <= 0:
            out.append((np.nan, v[i]))
            continue
        p = np.log(d1 / d2) / np.log(hs_ratio)
        ext = v[i] + d2 / (hs_ratio ** p - 1)
        out.append((p, ext))
    return out


def z0_of_fraction(f):
    return brentq(lambda z: np.pi * (z - z ** 3 / 3 + 2.0 / 3) - f * 4.0 / 3 * np.pi, -1, 1, xtol=1e-15)


def run_case(make_mesh, V, levels, k=30, label=""):
    res = []
    for n in levels:
        t0 = time.time()
        mesh, g = make_mesh(n)
        out = solve(mesh, g["z0"], g["a0"], k=k)
        lam, S = out["lam"], out["S"]
        mfrac = lam * S / V
        sumc = np.cumsum(S / V)      # sum m_j/(M lambda_j) = sum S_j / V
        res.append(dict(n=n, ndof=out["ndof"], lam=lam, mfrac=mfrac, sum=sumc,
                        slen=out["slen"], t=time.time() - t0))
        print(f"{label} n={n:4d} ndof={out['ndof']:7d} lam1={lam[0]:.10f} lam2={lam[1]:.10f} "
              f"m1/M={mfrac[0]:.8f} sum{len(lam)}={sumc[-1]:.8f} slen={out['slen']:.12f} "
              f"({time.time()-t0:.1f}s)", file=sys.stderr, flush=True)
    return res



DOC_FIELDS = ("fills", "cylinder", "budiansky_half")
FILLS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
#: Budiansky (1960), J. Aerospace Sci. 27, 161, Table 2: the half-full sphere's lambda1
BUDIANSKY_HALF = 1.5602


def main():
    import argparse

    from _report import SMOKE_HELP, emit

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fills", type=float, nargs="+", default=FILLS)
    parser.add_argument("--levels", type=int, nargs="+", default=[8, 16, 32, 64])
    parser.add_argument("--grade", type=float, default=2.0)
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args()
    fills = [0.5] if args.smoke else args.fills
    levels = [4, 8, 16] if args.smoke else args.levels
    xi = jnp_zeros(1, 1)[0]
    cylinder = run_case(lambda n: build_cylinder_mesh(1.0, n), np.pi, levels, k=4,
                        label="cylinder")
    exact = xi * np.tanh(xi)
    out = dict(cylinder=dict(lambda1_exact=float(exact),
                             lambda1_error=[float(r["lam"][0] / exact - 1) for r in cylinder]),
               fills={}, levels=levels, grade=args.grade)
    for f in fills:
        z0 = z0_of_fraction(f)
        volume = np.pi * (z0 - z0 ** 3 / 3 + 2.0 / 3)
        res = run_case(lambda n: build_sphere_mesh(z0, n, args.grade), volume, levels, k=4,
                       label=f"fill {f}")
        l1 = [float(r["lam"][0]) for r in res]
        mf = [float(r["mfrac"][0]) for r in res]
        order, lam1 = richardson(l1)[-1]
        mass_order, mass = richardson(mf)[-1]
        out["fills"][str(f)] = dict(
            level=float(z0), lambda1=float(lam1), lambda1_levels=l1, order=float(order),
            lambda2_finest=float(res[-1]["lam"][1]), slosh_mass_fraction=float(mass),
            slosh_mass_fraction_levels=mf, seconds=float(sum(r["t"] for r in res)))
    half = out["fills"].get("0.5")
    out["budiansky_half"] = dict(
        published=BUDIANSKY_HALF,
        error=(half["lambda1"] / BUDIANSKY_HALF - 1) if half else float("nan"))
    emit("sphere_slosh_reference", out, args.smoke)


if __name__ == "__main__":
    main()
