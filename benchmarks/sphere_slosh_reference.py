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
import logging
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import brentq
from scipy.special import jnp_zeros

from skfem import BilinearForm, Basis, ElementTriP2, LinearForm, MeshTri1, MeshTri2

logging.getLogger("skfem").setLevel(logging.ERROR)


# ----------------------------------------------------------------------------
# block-structured isoparametric mesh
# ----------------------------------------------------------------------------

def coons(bottom, right, top, left, P00, P10, P01, P11):
    """Transfinite map of the unit square; bottom(u)=X(u,0), top(u)=X(u,1),
    left(v)=X(0,v), right(v)=X(1,v).  Each curve returns array (2, n)."""
    def X(u, v):
        u = np.asarray(u, float)
        v = np.asarray(v, float)
        B, T, L, R = bottom(u), top(u), left(v), right(v)
        corner = ((1 - u) * (1 - v))[None] * P00[:, None] + (u * (1 - v))[None] * P10[:, None] \
            + ((1 - u) * v)[None] * P01[:, None] + (u * v)[None] * P11[:, None]
        return (1 - v)[None] * B + v[None] * T + (1 - u)[None] * L + u[None] * R - corner
    return X


def line(P, Q, g=None):
    """Straight segment P->Q, optional parameter grading g: [0,1]->[0,1]."""
    P = np.asarray(P, float)
    Q = np.asarray(Q, float)

    def c(s):
        s = np.asarray(s, float)
        if g is not None:
            s = g(s)
        return P[:, None] * (1 - s)[None] + Q[:, None] * s[None]
    return c


def arc(t0, t1, g=None):
    """Unit-circle arc from angle t0 to t1 (angles measured in the (r,z) plane)."""
    def c(s):
        s = np.asarray(s, float)
        if g is not None:
            s = g(s)
        t = t0 + (t1 - t0) * s
        return np.vstack([np.cos(t), np.sin(t)])
    return c


def patch_nodes(X, n, gu=None, gv=None):
    """P2 node grid (2n+1)^2 of a patch; returns coordinates (2, (2n+1)^2) and
    triangles as 6 x (2 n^2) array of local node indices (P2, skfem order)."""
    s = np.linspace(0.0, 1.0, 2 * n + 1)
    U, V = np.meshgrid(s, s, indexing="ij")  # U[i,j] = s_i
    u, v = U.ravel(), V.ravel()
    if gu is not None:
        u = gu(u)
    if gv is not None:
        v = gv(v)
    xy = X(u, v)
    N = 2 * n + 1
    idx = lambda i, j: i * N + j
    tris = []
    for i in range(n):
        for j in range(n):
            i0, j0 = 2 * i, 2 * j
            p00, p20, p02, p22 = idx(i0, j0), idx(i0 + 2, j0), idx(i0, j0 + 2), idx(i0 + 2, j0 + 2)
            # split along the diagonal p00-p22 (alternate for symmetry not needed)
            # tri 1: p00, p20, p22 ; edges (01),(12),(02)
            tris.append([p00, p20, p22, idx(i0 + 1, j0), idx(i0 + 2, j0 + 1), idx(i0 + 1, j0 + 1)])
            # tri 2: p00, p22, p02
            tris.append([p00, p22, p02, idx(i0 + 1, j0 + 1), idx(i0 + 1, j0 + 2), idx(i0, j0 + 1)])
    return xy, np.array(tris).T


def assemble_mesh(patches, n):
    """patches: list of (X, gu, gv). Merge nodes; return skfem MeshTri2."""
    allxy, alltri, off = [], [], 0
    for (X, gu, gv) in patches:
        xy, tri = patch_nodes(X, n, gu, gv)
        allxy.append(xy)
        alltri.append(tri + off)
        off += xy.shape[1]
    xy = np.hstack(allxy)
    tri6 = np.hstack(alltri)
    # merge coincident nodes (shared patch edges), tolerance-based
    from scipy.spatial import cKDTree
    pairs = cKDTree(xy.T).query_pairs(1e-11, output_type="ndarray")
    parent = np.arange(xy.shape[1])
    for i, j in pairs:          # few (only shared patch edges)
        ri, rj = parent[i], parent[j]
        while parent[ri] != ri:
            ri = parent[ri]
        while parent[rj] != rj:
            rj = parent[rj]
        if ri != rj:
            parent[max(ri, rj)] = min(ri, rj)
    for i in range(len(parent)):
        r = i
        while parent[r] != r:
            r = parent[r]
        parent[i] = r
    first, inv = np.unique(parent, return_inverse=True)
    xy = xy[:, first]
    tri6 = inv[tri6]
    # orientation: make all triangles counter-clockwise
    p = xy
    a, b, c = tri6[0], tri6[1], tri6[2]
    det = (p[0, b] - p[0, a]) * (p[1, c] - p[1, a]) - (p[0, c] - p[0, a]) * (p[1, b] - p[1, a])
    neg = det < 0
    # swap vertices 1<->2 and edge nodes (01)<->(02)
    tri6[:, neg] = tri6[[0, 2, 1, 5, 4, 3]][:, neg]
    # vertices only
    vert = np.unique(tri6[:3])
    vmap = -np.ones(xy.shape[1], dtype=np.int64)
    vmap[vert] = np.arange(len(vert))
    pv = xy[:, vert]
    t = vmap[tri6[:3]]
    m1 = MeshTri1(pv, t, sort_t=False)
    assert np.all(m1.t == t)
    # midpoint lookup: facet (i,j) -> edge node
    Nv = pv.shape[1]
    edges = [(0, 1, 3), (1, 2, 4), (0, 2, 5)]
    keys, vals = [], []
    for (i, j, k) in edges:
        vi, vj = t[i].astype(np.int64), t[j].astype(np.int64)
        lo, hi = np.minimum(vi, vj), np.maximum(vi, vj)
        keys.append(lo * Nv + hi)
        vals.append(tri6[k])
    keys = np.concatenate(keys)
    vals = np.concatenate(vals)
    uk, ui = np.unique(keys, return_index=True)
    uv = vals[ui]
    m2 = MeshTri2.from_mesh(m1)
    dl = m2.doflocs.copy()
    f = m1.facets.astype(np.int64)
    fk = np.minimum(f[0], f[1]) * Nv + np.maximum(f[0], f[1])
    pos = np.minimum(np.searchsorted(uk, fk), len(uk) - 1)
    assert np.all(uk[pos] == fk)
    # sanity: from_mesh puts straight midpoints at Nv + facet index
    assert np.allclose(dl[:, Nv:], 0.5 * (pv[:, f[0]] + pv[:, f[1]]))
    dl[:, Nv:] = xy[:, uv[pos]]
    m2 = MeshTri2(dl, m1.t, sort_t=False)
    return m2


def grading(q):
    """g(s) = s^q (concentrate at s=0); identity for q=1."""
    if q == 1:
        return None
    return lambda s: np.asarray(s, float) ** q


def build_sphere_mesh(z0, n, grade=1.0):
    a0 = np.sqrt(1 - z0 ** 2)
    A = np.array([0.0, -1.0])
    B = np.array([0.0, z0])
    C = np.array([a0, z0])
    tC = np.arctan2(z0, a0)
    tA = -np.pi / 2
    tM = 0.5 * (tC + tA)
    Mab = 0.5 * (A + B)
    Mbc = 0.5 * (B + C)
    Mca = np.array([np.cos(tM), np.sin(tM)])
    O = (Mab + Mbc + Mca) / 3.0
    g = grading(grade)
    # Patch C (corner at contact line): u: C->Mbc (surface), v: C->Mca (arc).
    #   grading toward u=0 and v=0 concentrates at C (and along the two
    #   boundary sides near C); shared edges Mbc-O (u=1) and Mca-O (v=1) are
    #   parametrised by v resp. u -> grade them consistently in neighbours.
    XC = coons(bottom=line(C, Mbc), right=line(Mbc, O), top=line(Mca, O), left=arc(tC, tM),
               P00=C, P10=Mbc, P01=Mca, P11=O)
    # Patch B (axis/surface corner): u: Mbc->B along surface? keep grading
    #   continuity: the surface side C..Mbc is graded from C; side Mbc..B is
    #   uniform.  Shared edge Mbc-O is graded from Mbc (v in patch C).
    #   Patch B: u: Mbc->O (graded like patch C's v), v: Mbc->B (uniform).
    XB = coons(bottom=line(Mbc, O), right=line(O, Mab), top=line(B, Mab), left=line(Mbc, B),
               P00=Mbc, P10=O, P01=B, P11=Mab)
    # Patch A: u: Mca->O (graded like patch C's u), v: Mca->A (arc, uniform).
    XA = coons(bottom=line(Mca, O), right=line(O, Mab), top=line(A, Mab), left=arc(tM, tA),
               P00=Mca, P10=O, P01=A, P11=Mab)
    patches = [(XC, g, g), (XB, g, None), (XA, g, None)]
    return assemble_mesh(patches, n), dict(a0=a0, z0=z0)


def build_cylinder_mesh(h, n):
    # two patches [0,0.5]x[-h,0] and [0.5,1]x[-h,0] (square cells for h=1)
    patches = []
    for (r0, r1) in [(0.0, 0.5), (0.5, 1.0)]:
        P00, P10, P01, P11 = (np.array(p, float) for p in ([r0, -h], [r1, -h], [r0, -h / 2], [r1, -h / 2]))
        patches.append((coons(line(P00, P10), line(P10, P11), line(P01, P11), line(P00, P01),
                              P00, P10, P01, P11), None, None))
        P00, P10, P01, P11 = (np.array(p, float) for p in ([r0, -h / 2], [r1, -h / 2], [r0, 0], [r1, 0]))
        patches.append((coons(line(P00, P10), line(P10, P11), line(P01, P11), line(P00, P01),
                              P00, P10, P01, P11), None, None))
    return assemble_mesh(patches, n), dict(a0=1.0, z0=0.0)


# ----------------------------------------------------------------------------
# FEM
# ----------------------------------------------------------------------------

@BilinearForm
def stiff(u, v, w):
    r = w.x[0]
    return (u.grad[0] * v.grad[0] + u.grad[1] * v.grad[1]) * r + u * v / r


@BilinearForm
def smass(u, v, w):
    return u * v * w.x[0]


@LinearForm
def r2load(v, w):
    return v * w.x[0] ** 2


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
    K = stiff.assemble(basis)
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
