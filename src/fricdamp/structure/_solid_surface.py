"""Boundary facets of solid meshes: extraction, areas, nodal area weights and normals.

Facets are rows of FE node indices: ``tri3`` (3), ``tri6`` (6: corners, then the mid-side
nodes of the edges c0-c1, c1-c2, c2-c0), ``quad4`` (4) and ``quad8`` (8: corners, then the
mid-side nodes of c0-c1, c1-c2, c2-c3, c3-c0), ordered right-handed about the outward
normal of the solid.

Nodal weights for node-to-node penalty contact: every quadratic facet is split into linear
sub-facets (tri6 -> 4 triangles, quad8 -> 4 corner triangles + the quadrilateral of its
mid-side nodes) and each node receives an equal share of every sub-facet touching it. The
shares are scaled so that each facet's weights sum to its area from Gauss quadrature of the
isoparametric facet (exact for flat facets; curved facets converge with the facet rule).
Consistent quadratic weights (the integrals of the shape functions) would be zero or negative
at the corners, useless as contact areas.
"""

from __future__ import annotations

import numpy as np

from fricdamp.errors import ModelError
from fricdamp.structure._solid_mesh import face_table

# linear sub-facets of each facet kind: triangles and quadrilaterals (local node indices)
_SUB = {
    3: ([(0, 1, 2)], []),
    6: ([(0, 3, 5), (3, 1, 4), (5, 4, 2), (3, 4, 5)], []),
    4: ([], [(0, 1, 2, 3)]),
    8: ([(0, 4, 7), (4, 1, 5), (5, 2, 6), (7, 6, 3)], [(4, 5, 6, 7)]),
}


def boundary_facets(elements: np.ndarray, cell_type: str) -> tuple[np.ndarray, np.ndarray]:
    """Boundary facets (faces of exactly one element) and their element.

    Returns
    -------
    facets : ndarray of int, shape (n_facets, 3|6|4|8)
        FE node indices, outward oriented for positively oriented elements.
    owners : ndarray of int, shape (n_facets,)
        Element of each facet.
    """
    faces = face_table(cell_type)
    nf, npf = faces.shape
    ncorner = 3 if cell_type.startswith("tetra") else 4
    all_faces = elements[:, faces].reshape(-1, npf)
    key = np.sort(all_faces[:, :ncorner], axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = counts[inv.ravel()] == 1
    owners = np.repeat(np.arange(len(elements)), nf)[once]
    return all_faces[once], owners


def _facet_kind(facets: np.ndarray) -> int:
    facets = np.asarray(facets)
    if facets.ndim != 2 or facets.shape[1] not in _SUB:
        raise ModelError(f"facets must have shape (n, 3|6|4|8), got {facets.shape}")
    return facets.shape[1]


def _shape_derivatives(npf: int) -> tuple[np.ndarray, np.ndarray]:
    """Derivatives ``(2, n_q, npf)`` of the facet shape functions and Gauss weights."""
    if npf in (3, 6):
        # 7-point degree-5 rule on the reference triangle (Strang & Fix / Dunavant)
        a1, a2 = 0.059715871789770, 0.797426985353087
        b1, b2 = 0.470142064105115, 0.101286507323456
        r = np.array([[1 / 3, 1 / 3], [a1, b1], [b1, a1], [b1, b1],
                      [a2, b2], [b2, a2], [b2, b2]])
        w = np.array([0.225, *[0.132394152788506] * 3, *[0.125939180544827] * 3]) / 2
        xi, eta = r[:, 0], r[:, 1]
        zeta = 1.0 - xi - eta
        if npf == 3:
            dxi = np.tile([-1.0, 1.0, 0.0], (len(w), 1))
            deta = np.tile([-1.0, 0.0, 1.0], (len(w), 1))
        else:   # corners (0,0) (1,0) (0,1), mids of 01, 12, 20
            z = np.zeros_like(xi)
            dxi = np.stack([1 - 4 * zeta, 4 * xi - 1, z, 4 * (zeta - xi), 4 * eta, -4 * eta], 1)
            deta = np.stack([1 - 4 * zeta, z, 4 * eta - 1, -4 * xi, 4 * xi, 4 * (zeta - eta)], 1)
        return np.stack([dxi, deta]), w
    g, gw = np.polynomial.legendre.leggauss(3)
    xi, eta = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    w = np.outer(gw, gw).ravel()
    sx = np.array([-1.0, 1.0, 1.0, -1.0])
    sy = np.array([-1.0, -1.0, 1.0, 1.0])
    X, Y = xi[:, None], eta[:, None]
    if npf == 4:
        dxi = sx * (1 + sy * Y) / 4
        deta = sy * (1 + sx * X) / 4
        return np.stack([dxi, deta]), w
    # quad8 serendipity: corners, then mids of 01 (y=-1), 12 (x=1), 23 (y=1), 30 (x=-1)
    dxi_c = sx * (1 + sy * Y) * (2 * sx * X + sy * Y) / 4
    deta_c = sy * (1 + sx * X) * (sx * X + 2 * sy * Y) / 4
    my = np.array([-1.0, 1.0])      # mids 4 and 6 at y = -1, +1 (vary in x)
    mx = np.array([1.0, -1.0])      # mids 5 and 7 at x = +1, -1 (vary in y)
    dxi_m = np.empty((len(w), 4))
    deta_m = np.empty((len(w), 4))
    dxi_m[:, [0, 2]] = -X * (1 + my * Y)
    deta_m[:, [0, 2]] = my * (1 - X ** 2) / 2
    dxi_m[:, [1, 3]] = mx * (1 - Y ** 2) / 2
    deta_m[:, [1, 3]] = -Y * (1 + mx * X)
    return np.stack([np.hstack([dxi_c, dxi_m]), np.hstack([deta_c, deta_m])]), w


def facet_vector_areas(nodes: np.ndarray, facets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Areas [m^2] ``(n,)`` and vector areas ``int n dA`` [m^2] ``(n, 3)`` of facets."""
    npf = _facet_kind(facets)
    dN, w = _shape_derivatives(npf)
    x = nodes[facets]                                     # (n, npf, 3)
    t1 = np.einsum("qk,nkd->nqd", dN[0], x)
    t2 = np.einsum("qk,nkd->nqd", dN[1], x)
    c = np.cross(t1, t2)                                  # (n, q, 3)
    area = np.einsum("nq,q->n", np.linalg.norm(c, axis=2), w)
    vec = np.einsum("nqd,q->nd", c, w)
    return area, vec


def _sub_facet_parts(nodes, facets):
    """(facet, node, vector area share) triples of the linear sub-facets."""
    npf = _facet_kind(facets)
    tris, quads = _SUB[npf]
    fid, nid, vec = [], [], []
    x = nodes[facets]
    for tri in tris:
        a, b, c = (x[:, k] for k in tri)
        v = 0.5 * np.cross(b - a, c - a) / 3.0
        for k in tri:
            fid.append(np.arange(len(facets)))
            nid.append(facets[:, k])
            vec.append(v)
    for quad in quads:
        a, b, c, d = (x[:, k] for k in quad)
        v = 0.5 * np.cross(c - a, d - b) / 4.0
        for k in quad:
            fid.append(np.arange(len(facets)))
            nid.append(facets[:, k])
            vec.append(v)
    return np.concatenate(fid), np.concatenate(nid), np.concatenate(vec)


def tributary_areas(nodes: np.ndarray, facets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positive nodal area weights of facets, summing to the facets' area.

    Returns
    -------
    node_ids : ndarray of int, shape (n,)
        Sorted FE nodes of the facets.
    areas : ndarray, shape (n,)
        Area weight [m^2] of each node.
    """
    facets = np.asarray(facets, dtype=np.int64)
    _facet_kind(facets)
    if len(facets) == 0:
        return np.empty(0, np.int64), np.empty(0)
    fid, nid, vec = _sub_facet_parts(nodes, facets)
    share = np.linalg.norm(vec, axis=1)
    chord_area = np.bincount(fid, share, minlength=len(facets))
    true_area, _ = facet_vector_areas(nodes, facets)
    share = share * (true_area / chord_area)[fid]
    node_ids, inv = np.unique(nid, return_inverse=True)
    return node_ids, np.bincount(inv, share, minlength=len(node_ids))


def node_normals(nodes: np.ndarray, facets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Area-weighted outward unit normals at the facets' nodes.

    Returns
    -------
    node_ids : ndarray of int, shape (n,)
    normals : ndarray, shape (n, 3)
        Unit normals: the normalised sum of the vector areas of the sub-facets (shared
        equally among their nodes) touching each node.
    """
    facets = np.asarray(facets, dtype=np.int64)
    _facet_kind(facets)
    if len(facets) == 0:
        return np.empty(0, np.int64), np.empty((0, 3))
    _, nid, vec = _sub_facet_parts(nodes, facets)
    node_ids, inv = np.unique(nid, return_inverse=True)
    n = np.stack([np.bincount(inv, vec[:, d], minlength=len(node_ids)) for d in range(3)], 1)
    return node_ids, n / np.linalg.norm(n, axis=1, keepdims=True)
