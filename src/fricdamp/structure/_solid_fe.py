"""scikit-fem discretisation of a :class:`SolidMesh`: nodes, bases and element matrices.

The finite elements, mappings, quadrature rules and DOF numbering are scikit-fem's
(``ElementTetP1``, ``ElementTetP2``, ``ElementHex1``, ``ElementHexS2`` on ``MeshTet1``,
``MeshTet2`` for curved tet10 meshes, ``MeshHex1``). Two assemblies are offered:

* ``"skfem"``: ``asm(linear_elasticity(lam, mu), basis)`` and a vector mass form on an
  ``ElementVector`` basis -- the reference, about 10x slower for quadratic elements because
  skfem evaluates the form once per pair of the 30 x 30 (tet10) vector basis functions;
* ``"fast"`` (default): the same integrals from the same scalar basis (gradients and
  ``dx`` = quadrature weight x |det J| taken from skfem), written as one batched matrix
  product per block of elements, ``S = (G dx) G^T`` with ``G`` the (3 n_b, n_q) gradients,
  and ``K_e[a i, b j] = lam S[a i, b j] + mu S[a j, b i] + mu delta_ij sum_k S[a k, b k]``.
  The unit tests check it equals the reference to round-off.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError
from fricdamp.structure._solid_mesh import SK_HEX, SolidMesh, corner_count, edge_table

#: element name -> (meshio cell type of the FE nodes, skfem element name, quadrature order)
ELEMENTS = {
    "tet4": ("tetra", "ElementTetP1", 2),        # mass integrand degree 2
    "tet10": ("tetra10", "ElementTetP2", 4),     # mass degree 4 (stiffness 2 if straight)
    "hex8": ("hexahedron", "ElementHex1", 3),    # 2x2x2 Gauss
    "hex20": ("hexahedron20", "ElementHexS2", 5),  # 3x3x3 Gauss
}
DEFAULT_ELEMENT = {"tetra": "tet4", "tetra10": "tet10", "hexahedron": "hex8",
                   "hexahedron20": "hex20"}
ALLOWED_ELEMENTS = {"tetra": ("tet4", "tet10"), "tetra10": ("tet10",),
                    "hexahedron": ("hex8", "hex20"), "hexahedron20": ("hex20",)}
_STRAIGHT_TOL = 1e-6   # mid-side offset from the chord midpoint / chord length


@dataclass
class Discretisation:
    """FE nodes of a mesh and the skfem objects to integrate over it (internal)."""

    element_type: str
    cell_type: str                 # meshio type of ``elements``
    nodes: np.ndarray              # (n_nodes, 3)
    elements: np.ndarray           # (n_el, npe) FE node indices, meshio ordering
    point_node: np.ndarray         # (n_points,) FE node of each mesh point or -1
    generated: bool                # mid-side nodes generated (not in the mesh)
    skmesh: object
    skelem: object                 # scalar skfem element instance
    intorder: int
    sk2node: np.ndarray            # FE node of each scalar skfem DOF


def resolve_element(mesh: SolidMesh, element: str | None) -> str:
    """Element name for a mesh: the default of its cell type or a checked user choice."""
    if element is None:
        return DEFAULT_ELEMENT[mesh.cell_type]
    allowed = ALLOWED_ELEMENTS[mesh.cell_type]
    if element not in allowed:
        raise ModelError(f"element must be one of {allowed} for a {mesh.cell_type} mesh "
                         f"(or None for {DEFAULT_ELEMENT[mesh.cell_type]}), got {element!r}")
    return element


def discretise(mesh: SolidMesh, element_type: str) -> Discretisation:
    """Build the skfem mesh and the FE node numbering of ``mesh`` for ``element_type``.

    FE nodes: the mesh points used by the cells in increasing point index (so node ``i`` is
    point ``i`` when every point is used), then generated mid-side nodes (tet10 on a tetra
    mesh, hex20 on a hexahedron mesh) in skfem's edge order.
    """
    import skfem

    fe_type, elem_name, intorder = ELEMENTS[element_type]
    nv = corner_count(mesh.cell_type)
    cells = mesh.cells
    corners = cells[:, :nv]
    used_vertices, inv = np.unique(corners, return_inverse=True)
    vcell = inv.reshape(corners.shape)                       # vertex index per cell corner
    tv = vcell[:, SK_HEX] if nv == 8 else vcell              # skfem local vertex order
    vxyz = mesh.points[used_vertices]
    mesh_cls = skfem.MeshHex1 if nv == 8 else skfem.MeshTet1
    skmesh = mesh_cls(np.ascontiguousarray(vxyz.T), np.ascontiguousarray(tv.T), validate=False)
    quadratic_fe = fe_type in ("tetra10", "hexahedron20")
    quadratic_mesh = cells.shape[1] > nv

    used_points = np.unique(cells)
    point_node = np.full(len(mesh.points), -1, dtype=np.int64)
    point_node[used_points] = np.arange(len(used_points))
    nodes = mesh.points[used_points]
    sk2node = point_node[used_vertices]
    elements = point_node[corners]
    generated = False
    if quadratic_fe:
        edges = np.asarray(skmesh.edges)                    # (2, n_edges), sorted pairs
        n_vert = len(used_vertices)
        keys = edges[0].astype(np.int64) * n_vert + edges[1]
        local = edge_table(mesh.cell_type)
        a, b = vcell[:, local[:, 0]], vcell[:, local[:, 1]]
        cell_edges = np.searchsorted(keys, np.minimum(a, b) * n_vert + np.maximum(a, b))
        if quadratic_mesh:
            mids = cells[:, nv:]
            edge_point = np.full(edges.shape[1], -1, dtype=np.int64)
            edge_point[cell_edges.ravel()] = mids.ravel()
            if np.any(edge_point[cell_edges] != mids):
                raise ModelError("cells sharing an edge have different mid-side points "
                                 "(non-conforming quadratic mesh)")
            edge_nodes = point_node[edge_point]
            ends = mesh.points[used_vertices[edges]]             # (2, n_edges, 3)
            chord = np.linalg.norm(ends[1] - ends[0], axis=1)
            offset = np.linalg.norm(mesh.points[edge_point] - 0.5 * (ends[0] + ends[1]), axis=1)
            if np.any(offset > _STRAIGHT_TOL * chord):
                if nv == 8:
                    raise ModelError("hexahedron20 cells with curved edges are not supported "
                                     "(mid-side points off the chord midpoints); use tetra10 "
                                     "or straight-edged hexahedra")
                skmesh = skfem.MeshTet2(
                    np.ascontiguousarray(np.hstack([vxyz.T, mesh.points[edge_point].T])),
                    np.ascontiguousarray(tv.T), validate=False)
        else:
            generated = True
            edge_nodes = len(nodes) + np.arange(edges.shape[1])
            nodes = np.vstack([nodes, 0.5 * (vxyz[edges[0]] + vxyz[edges[1]])])
        sk2node = np.concatenate([sk2node, edge_nodes])
        elements = np.hstack([elements, sk2node[n_vert + cell_edges]])
    return Discretisation(element_type=element_type, cell_type=fe_type, nodes=nodes,
                          elements=elements, point_node=point_node, generated=generated,
                          skmesh=skmesh, skelem=getattr(skfem, elem_name)(),
                          intorder=intorder, sk2node=sk2node)


def scalar_basis(disc: Discretisation):
    """skfem scalar basis over all elements, after checking the element Jacobians."""
    import skfem

    try:
        basis = skfem.Basis(disc.skmesh, disc.skelem, intorder=disc.intorder)
        det = basis.mapping.detDF(basis.X)
    except Exception as exc:  # noqa: BLE001 - skfem raises a bare Exception for det J = 0
        raise ModelError(f"degenerate elements (zero Jacobian determinant): {exc}") from exc
    bad = np.flatnonzero(np.any(np.asarray(det) <= 0.0, axis=-1))
    if bad.size:
        raise ModelError(f"{bad.size} inverted or degenerate element(s) (Jacobian determinant "
                         f"<= 0), first: cell {bad[0]}; check the node ordering "
                         f"(meshio/VTK convention) and the mesh quality")
    n_sk = basis.N
    if n_sk != len(disc.sk2node):
        raise ModelError(f"internal: skfem has {n_sk} DOFs, expected {len(disc.sk2node)}")
    return basis


def element_matrices(basis, elements: np.ndarray, lam: np.ndarray, mu: np.ndarray,
                     rho: np.ndarray):
    """Stiffness ``(n, 3 nb, 3 nb)`` and scalar mass ``(n, nb, nb)`` of some elements.

    ``lam``, ``mu`` [Pa] and ``rho`` [kg/m^3] are given per element of ``elements``;
    local ordering (basis function a, component i) -> ``3 a + i``.
    """
    nb = basis.Nbfun
    grads = np.stack([basis.basis[a][0].grad[:, elements] for a in range(nb)])  # (nb,3,n,q)
    values = np.stack([np.asarray(basis.basis[a][0])[elements] for a in range(nb)])  # (nb,n,q)
    dx = basis.dx[elements]                                                    # (n,q)
    n = len(elements)
    g = grads.transpose(2, 0, 1, 3).reshape(n, 3 * nb, -1)
    s = ((g * dx[:, None, :]) @ g.transpose(0, 2, 1)).reshape(n, nb, 3, nb, 3)
    trace = np.einsum("eakbk->eab", s)
    ke = lam[:, None, None, None, None] * s + mu[:, None, None, None, None] * s.transpose(
        0, 1, 4, 3, 2)
    for i in range(3):
        ke[:, :, i, :, i] += mu[:, None, None] * trace
    ke = ke.reshape(n, 3 * nb, 3 * nb)
    v = values.transpose(1, 0, 2)
    me = rho[:, None, None] * ((v * dx[:, None, :]) @ v.transpose(0, 2, 1))
    return ke, me


def assemble_fast(basis, sk2node: np.ndarray, elements: np.ndarray, lam, mu, rho,
                  n_nodes: int, *, block_bytes: float = 64e6) -> tuple[sp.csr_matrix,
                                                                     sp.csr_matrix]:
    """Assemble K [N/m] and M [kg] over ``elements`` (indices) in node-major DOF order."""
    nb = basis.Nbfun
    n_dof = 3 * n_nodes
    itype = np.int32 if n_dof < 2 ** 31 - 1 else np.int64
    edofs = sk2node[np.asarray(basis.element_dofs)].T.astype(itype)     # (n_el, nb) nodes
    n_el, nk, nm = len(elements), (3 * nb) ** 2, nb * nb
    rows, cols = np.empty(n_el * nk, itype), np.empty(n_el * nk, itype)
    kdata = np.empty(n_el * nk)
    mrows, mcols = np.empty(n_el * nm, itype), np.empty(n_el * nm, itype)
    mdata = np.empty(n_el * nm)
    block = max(1, int(block_bytes // (8 * 4 * nk)))
    for start in range(0, n_el, block):
        sl = slice(start, min(start + block, n_el))
        ke, me = element_matrices(basis, elements[sl], lam[sl], mu[sl], rho[sl])
        nodes = edofs[elements[sl]]
        dofs = (3 * nodes[:, :, None] + np.arange(3, dtype=itype)).reshape(len(nodes), -1)
        ks, ms = slice(sl.start * nk, sl.stop * nk), slice(sl.start * nm, sl.stop * nm)
        rows[ks].reshape(ke.shape)[...] = dofs[:, :, None]
        cols[ks].reshape(ke.shape)[...] = dofs[:, None, :]
        kdata[ks] = ke.ravel()
        mrows[ms].reshape(me.shape)[...] = nodes[:, :, None]
        mcols[ms].reshape(me.shape)[...] = nodes[:, None, :]
        mdata[ms] = me.ravel()
    K = sp.coo_matrix((kdata, (rows, cols)), shape=(n_dof, n_dof)).tocsr()
    Ms = sp.coo_matrix((mdata, (mrows, mcols)), shape=(n_nodes, n_nodes)).tocsr()
    M = sp.kron(Ms, sp.identity(3, format="csr"), format="csr")
    return symmetrised(K), symmetrised(M)


def symmetrised(A: sp.csr_matrix) -> sp.csr_matrix:
    """``(A + A^T) / 2``: removes the round-off asymmetry of the summation order."""
    return (0.5 * (A + A.T)).tocsr()


def assemble_skfem(disc: Discretisation, elements: np.ndarray, lam, mu, rho,
                   n_nodes: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Reference assembly with skfem ``asm``, ``linear_elasticity`` and a vector mass form."""
    import skfem
    from skfem.helpers import dot
    from skfem.models.elasticity import linear_elasticity

    vbasis = skfem.Basis(disc.skmesh, skfem.ElementVector(disc.skelem), intorder=disc.intorder,
                         elements=elements)
    nq = vbasis.X.shape[-1]
    per_qp = [np.repeat(np.asarray(x, float)[:, None], nq, axis=1) for x in (lam, mu, rho)]

    @skfem.BilinearForm
    def mass(u, v, w):
        return w["rho"] * dot(u, v)

    K_sk = skfem.asm(linear_elasticity(per_qp[0], per_qp[1]), vbasis)
    M_sk = skfem.asm(mass, vbasis, rho=per_qp[2])
    # vector DOF numbering of skfem (per vertex / edge, 3 components) -> 3 * node + c
    perm = np.empty(vbasis.N, dtype=np.int64)
    n_vert = vbasis.nodal_dofs.shape[1]
    for c in range(3):
        perm[vbasis.nodal_dofs[c]] = 3 * disc.sk2node[:n_vert] + c
        if vbasis.edge_dofs is not None and vbasis.edge_dofs.size:
            perm[vbasis.edge_dofs[c]] = 3 * disc.sk2node[n_vert:] + c
    n_dof = 3 * n_nodes

    def permute(A):
        A = A.tocoo()
        return symmetrised(sp.csr_matrix((A.data, (perm[A.row], perm[A.col])),
                                         shape=(n_dof, n_dof)))

    return permute(K_sk), permute(M_sk)


def assemble_geometric(basis, sk2node: np.ndarray, lam, mu, u: np.ndarray, n_nodes: int, *,
                       block_bytes: float = 64e6) -> sp.csr_matrix:
    """Geometric (initial-stress) stiffness ``K_sigma`` [N/m] of the stress of ``u``.

    ``u`` (n_nodes, 3) is a displacement field [m]; its small-strain stress
    ``sigma = lam tr(eps) I + 2 mu eps`` at every quadrature point gives
    ``K_sigma[3a + i, 3b + i] = int grad N_a . sigma . grad N_b dV`` (the same for each
    component i, zero between components): the second variation of the Green-Lagrange strain
    energy of the prestress, e.g. Zienkiewicz, Taylor & Fox (2014), *The Finite Element
    Method for Solid and Structural Mechanics*, 7th ed., sec. 10.3 (buckling). All elements
    are used (``lam``, ``mu`` per element [Pa]).
    """
    nb = basis.Nbfun
    edofs = sk2node[np.asarray(basis.element_dofs)].T                # (n_el, nb) FE nodes
    n_el = edofs.shape[0]
    n_q = basis.dx.shape[1]
    block = max(1, int(block_bytes // (8 * 3 * nb * n_q * 4)))
    rows = np.empty(n_el * nb * nb, dtype=np.int64)
    cols = np.empty_like(rows)
    data = np.empty(n_el * nb * nb)
    for start in range(0, n_el, block):
        sl = np.arange(start, min(start + block, n_el))
        g = np.stack([basis.basis[a][0].grad[:, sl] for a in range(nb)], axis=1)  # (3,nb,n,q)
        ue = u[edofs[sl]]                                                 # (n, nb, 3)
        H = np.einsum("eai,jaeq->eijq", ue, g)                           # du_i/dx_j
        eps = 0.5 * (H + H.transpose(0, 2, 1, 3))
        tr = np.einsum("eiiq->eq", eps)
        sig = 2.0 * mu[sl, None, None, None] * eps
        for i in range(3):
            sig[:, i, i, :] += lam[sl, None] * tr
        kg = np.einsum("jaeq,ejkq,kbeq,eq->eab", g, sig, g, basis.dx[sl], optimize=True)
        nodes = edofs[sl]
        k = slice(start * nb * nb, (start + sl.size) * nb * nb)
        rows[k] = np.repeat(nodes, nb, axis=1).ravel()
        cols[k] = np.tile(nodes, (1, nb)).ravel()
        data[k] = kg.ravel()
    Ks = sp.coo_matrix((data, (rows, cols)), shape=(n_nodes, n_nodes)).tocsr()
    return symmetrised(sp.kron(Ks, sp.identity(3, format="csr"), format="csr"))
