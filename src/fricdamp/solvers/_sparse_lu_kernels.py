"""Numeric kernels of the dense-block LU of :mod:`fricdamp.solvers._sparse_lu`.

The factorisation (:func:`_block_numeric`: left-looking over block columns, partial
pivoting inside each diagonal block, the threshold rule against the blocks below, the
element growth of the factors) and the solve of one or two right-hand sides
(:func:`_block_solve2`), with the numba intrinsics that handle stored rows of 4, 8, 12 or
16 doubles as LLVM vectors. The symbolic analysis that lays out the blocks, and the classes
that call these kernels, are in :mod:`fricdamp.solvers._sparse_lu`.

The kernels and the intrinsics they inline live in this one file: numba's on-disk cache of
a kernel is keyed to the source file of the kernel, not to the files of the functions it
inlines, so a change to an intrinsic kept elsewhere would leave stale cached code.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

from fricdamp._numba_cache import njit


@njit(cache=True, nogil=True)
def _clear(where, Lp, Li, Up, Ui, J):  # pragma: no cover - compiled
    for p in range(Up[J], Up[J + 1]):
        where[Ui[p]] = -1
    where[J] = -1
    for p in range(Lp[J], Lp[J + 1]):
        where[Li[p]] = -1


# ---------------------------------------------------------------------------- row vectors
# Rows of W doubles (W the padded row length of a block, a multiple of 4) handled as W / 4
# LLVM vectors <4 x double>: numba's loops over such rows stay scalar (the index of every
# element goes through negative-index wrap-around, so neither the loop nor the SLP
# vectoriser sees consecutive addresses), and a row of 12 held in scalars took 12 scalar
# multiplies and subtractions per term. These intrinsics emit the vector multiplies and
# subtractions themselves, lane by lane in the same order (no fused multiply-add, no
# reassociation): the same bits as the scalar loops. W must be a compile-time constant (a
# literal at the call, through inlined helpers).
_I32 = ir.IntType(32)
_V4 = ir.VectorType(ir.DoubleType(), 4)


def _literal(value, what):
    if not isinstance(value, types.IntegerLiteral) or value.literal_value % 4:
        raise numba.core.errors.TypingError(f"{what} must be a compile-time multiple of 4")
    return value.literal_value


def _splat(builder, x):
    v = builder.insert_element(ir.Constant(_V4, None), x, ir.Constant(_I32, 0))
    return builder.shuffle_vector(v, ir.Constant(_V4, None),
                                  ir.Constant(ir.VectorType(_I32, 4), [0, 0, 0, 0]))


def _at(builder, data, off):
    return builder.gep(data, [off], inbounds=True)


def _offset(builder, base, k):
    return builder.add(base, ir.Constant(base.type, k))


def _vload(builder, data, off):
    return builder.load(builder.bitcast(_at(builder, data, off), _V4.as_pointer()), align=8)


def _vstore(builder, v, data, off):
    builder.store(v, builder.bitcast(_at(builder, data, off), _V4.as_pointer()), align=8)


def _llvm_function(builder, name, ret, args):
    return cgutils.get_or_insert_function(builder.module, ir.FunctionType(ret, args), name)


def _data(context, builder, typ, value):
    return context.make_array(typ)(context, builder, value).data


def _row_slots(builder, data, off, W):
    """Allocas holding the W / 4 vectors of the row at ``data[off]`` (promoted to registers
    by LLVM)."""
    slots = []
    for g in range(W // 4):
        slot = cgutils.alloca_once(builder, _V4)
        builder.store(_vload(builder, data, _offset(builder, off, 4 * g)), slot)
        slots.append(slot)
    return slots


def _store_row(builder, slots, data, off):
    for g, slot in enumerate(slots):
        _vstore(builder, builder.load(slot), data, _offset(builder, off, 4 * g))


@intrinsic
def _sub_rows(typingctx, width, Y, o, A, a0, X, x0, m):  # pragma: no cover - compiled
    """``Y[o: o+W] -= sum_k A[a0 + k] * X[x0 + W k: x0 + W k + W]`` for k < m, in order of
    k, the row held in registers (the row of Y must not be one of the rows of X read)."""
    W = _literal(width, "the row width")
    ip = types.intp
    sig = types.void(width, Y, ip, A, ip, X, ip, ip)

    def codegen(context, builder, signature, args):
        _, y, o, a, a0, x, x0, m = args
        ys = _data(context, builder, signature.args[1], y)
        as_ = _data(context, builder, signature.args[3], a)
        xs = _data(context, builder, signature.args[5], x)
        acc = _row_slots(builder, ys, o, W)
        with cgutils.for_range(builder, m) as loop:
            k = loop.index
            b = builder.add(x0, builder.mul(k, ir.Constant(k.type, W)))
            av = _splat(builder, builder.load(_at(builder, as_, builder.add(a0, k))))
            for g, slot in enumerate(acc):
                xv = _vload(builder, xs, _offset(builder, b, 4 * g))
                builder.store(builder.fsub(builder.load(slot), builder.fmul(av, xv)), slot)
        _store_row(builder, acc, ys, o)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _axpy_row(typingctx, width, Y, o, a, U, u0):  # pragma: no cover - compiled
    """``Y[o: o+W] -= a * U[u0: u0+W]``."""
    W = _literal(width, "the row width")
    ip = types.intp
    sig = types.void(width, Y, ip, types.float64, U, ip)

    def codegen(context, builder, signature, args):
        _, y, o, a, u, u0 = args
        ys = _data(context, builder, signature.args[1], y)
        us = _data(context, builder, signature.args[4], u)
        av = _splat(builder, a)
        for g in range(W // 4):
            yo = _offset(builder, o, 4 * g)
            prod = builder.fmul(av, _vload(builder, us, _offset(builder, u0, 4 * g)))
            _vstore(builder, builder.fsub(_vload(builder, ys, yo), prod), ys, yo)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _solve_row_upper(typingctx, width, Y, o, U, inv, n, amax):  # pragma: no cover - compiled
    """Row ``y = Y[o: o+W]`` of a block below the diagonal block of a panel, times U^-1:
    for c < n, ``a = y_c * inv[c]``, ``y -= a * U[cW: cW+W]`` (row c of U with zeros at
    and left of the diagonal), ``y_c = a`` -- the operations of the right-looking panel
    update on this row, in the same order. ``amax[c]`` becomes ``max(amax[c], |y_c|)``
    with y_c before the scaling (the column below the pivot, for the threshold rule;
    a NaN leaves it unchanged, as the comparison ``a > amax`` of the scalar loop did).
    The steps are unrolled over c < W (lanes of y by constant index), each taken if
    c < n."""
    W = _literal(width, "the row width")
    ip = types.intp
    sig = types.void(width, Y, ip, U, inv, ip, amax)

    def codegen(context, builder, signature, args):
        _, y, o, u, iv, n, am = args
        ys = _data(context, builder, signature.args[1], y)
        us = _data(context, builder, signature.args[3], u)
        ivs = _data(context, builder, signature.args[4], iv)
        ams = _data(context, builder, signature.args[6], am)
        fabs = _llvm_function(builder, "llvm.fabs.f64", ir.DoubleType(), [ir.DoubleType()])
        row = _row_slots(builder, ys, o, W)
        for c in range(W):
            cc = ir.Constant(n.type, c)
            with builder.if_then(builder.icmp_signed("<", cc, n), likely=True):
                lane = ir.Constant(_I32, c % 4)
                yc = builder.extract_element(builder.load(row[c // 4]), lane)
                ay = builder.call(fabs, [yc])
                pa = _at(builder, ams, cc)
                m0 = builder.load(pa)
                builder.store(builder.select(builder.fcmp_ordered(">", ay, m0), ay, m0), pa)
                a = builder.fmul(yc, builder.load(_at(builder, ivs, cc)))
                av = _splat(builder, a)
                for g, slot in enumerate(row):
                    uv = _vload(builder, us, ir.Constant(n.type, c * W + 4 * g))
                    v = builder.fsub(builder.load(slot), builder.fmul(av, uv))
                    if g == c // 4:
                        v = builder.insert_element(v, a, lane)
                    builder.store(v, slot)
        _store_row(builder, row, ys, o)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _absmax(typingctx, Y, o, count):  # pragma: no cover - compiled
    """``max |Y[o: o+count]|`` (count a multiple of 4), NaN if one of them is NaN (LLVM's
    ``maximum``, which propagates NaN)."""
    ip = types.intp
    sig = types.float64(Y, ip, ip)

    def codegen(context, builder, signature, args):
        y, o, count = args
        ys = _data(context, builder, signature.args[0], y)
        dbl = ir.DoubleType()
        vmax = _llvm_function(builder, "llvm.maximum.v4f64", _V4, [_V4, _V4])
        vabs = _llvm_function(builder, "llvm.fabs.v4f64", _V4, [_V4])
        smax = _llvm_function(builder, "llvm.maximum.f64", dbl, [dbl, dbl])
        acc = cgutils.alloca_once(builder, _V4)
        builder.store(ir.Constant(_V4, [0.0] * 4), acc)
        four = ir.Constant(count.type, 4)
        with cgutils.for_range(builder, builder.sdiv(count, four)) as loop:
            v = builder.call(vabs, [_vload(builder, ys, builder.add(o, builder.mul(
                loop.index, four)))])
            builder.store(builder.call(vmax, [builder.load(acc), v]), acc)
        v = builder.load(acc)
        lanes = [builder.extract_element(v, ir.Constant(_I32, i)) for i in range(4)]
        return builder.call(smax, [builder.call(smax, lanes[:2]), builder.call(smax, lanes[2:])])

    return sig, codegen


@njit(cache=True, nogil=True, inline="always")
def _nanmax(x, y):  # pragma: no cover - compiled
    """max(x, y), NaN if either is NaN."""
    return x if (x > y or x != x) else y


@njit(cache=True, nogil=True, inline="always")
def _column_w(W, J, nJ, S, bsz, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff, piv, pstart,
              threshold, where, upad, inv, amax, adiag, stats):  # pragma: no cover - compiled
    """Block column J of :func:`_block_numeric` when its rows are W long (``ld[J] == W``, a
    literal): the U blocks, then the panel. Returns False if a pivot fails. ``stats[0]``
    and ``stats[1]`` become the largest |entry| of L and of U so far (NaN-propagating).

    The panel first factorises the diagonal block (partial pivoting inside it), keeping
    the rows of U padded with zeros (``upad``) and the reciprocal pivots, then takes each
    row of the blocks below through all pivot columns at once (:func:`_solve_row_upper`),
    and checks the threshold rule of every column at the end: the operations of the
    right-looking loop over pivot columns, element by element in the same order (same bits),
    each row loaded and stored once instead of once per pivot column.
    """
    for p in range(Up[J], Up[J + 1]):
        K = Ui[p]
        nK = bsz[K]
        lK = ld[K]
        x0 = Uoff[p]
        d0 = Doff[K]
        q0 = pstart[K]
        for c in range(nK):                     # row interchanges of block K
            r = piv[q0 + c]
            if r != c:
                for cc in range(W):
                    t = S[x0 + c * W + cc]
                    S[x0 + c * W + cc] = S[x0 + r * W + cc]
                    S[x0 + r * W + cc] = t
        for r in range(1, nK):                  # unit lower solve with L_KK
            _sub_rows(W, S, x0 + r * W, S, d0 + r * lK, S, x0, r)
        stats[1] = _nanmax(stats[1], _absmax(S, x0, nK * W))     # U_KJ is final
        for q in range(Lp[K], Lp[K + 1]):       # X_IJ -= L_IK U_KJ
            l0 = Loff[q]
            y0 = where[Li[q]]
            for r in range(bsz[Li[q]]):
                _sub_rows(W, S, y0 + r * W, S, l0 + r * lK, S, x0, nK)
    # ---- panel: diagonal block, pivots inside it (multipliers <= 1)
    d0 = Doff[J]
    q0 = pstart[J]
    for c in range(nJ):
        r_best = c
        a_best = abs(S[d0 + c * W + c])
        for r in range(c + 1, nJ):
            a = abs(S[d0 + r * W + c])
            if a > a_best:
                a_best = a
                r_best = r
        if not (a_best > 0.0) or not math.isfinite(a_best):
            return False
        adiag[c] = a_best
        piv[q0 + c] = r_best
        if r_best != c:
            for cc in range(W):
                t = S[d0 + c * W + cc]
                S[d0 + c * W + cc] = S[d0 + r_best * W + cc]
                S[d0 + r_best * W + cc] = t
        iv = 1.0 / S[d0 + c * W + c]
        inv[c] = iv
        # the pivot row right of the pivot, zeros elsewhere: the row updates run over
        # whole rows, subtracting exact zeros left of column c + 1
        for cc in range(W):
            upad[c * W + cc] = S[d0 + c * W + cc] if cc > c else 0.0
        for r in range(c + 1, nJ):
            a = S[d0 + r * W + c] * iv
            _axpy_row(W, S, d0 + r * W, a, upad, c * W)
            S[d0 + r * W + c] = a
    # ---- the blocks below, row by row; then the threshold rule of every pivot column
    for c in range(nJ):
        amax[c] = 0.0
    for p in range(Lp[J], Lp[J + 1]):
        l0 = Loff[p]
        nI = bsz[Li[p]]
        for r in range(nI):
            _solve_row_upper(W, S, l0 + r * W, upad, inv, nJ, amax)
        stats[0] = _nanmax(stats[0], _absmax(S, l0, nI * W))
    u = _absmax(upad, 0, nJ * W)
    for c in range(nJ):
        u = _nanmax(u, adiag[c])
        if adiag[c] < threshold * amax[c]:
            return False
    stats[1] = _nanmax(stats[1], u)
    return True


@njit(cache=True, nogil=True, inline="always")
def _column_any(J, nJ, lJ, S, bsz, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff, piv, pstart,
                threshold, where, urow):  # pragma: no cover - compiled
    """Block column J of :func:`_block_numeric` for any row length (scalar loops):
    returns False if a pivot fails."""
    # ---- U blocks of column J, in topological order
    for p in range(Up[J], Up[J + 1]):
        K = Ui[p]
        nK = bsz[K]
        lK = ld[K]
        X = S[Uoff[p]: Uoff[p] + nK * lJ]
        D = S[Doff[K]: Doff[K] + nK * lK]
        q0 = pstart[K]
        for c in range(nK):                     # row interchanges of block K
            r = piv[q0 + c]
            if r != c:
                for cc in range(lJ):
                    t = X[c * lJ + cc]
                    X[c * lJ + cc] = X[r * lJ + cc]
                    X[r * lJ + cc] = t
        for c in range(nK):                     # unit lower solve with L_KK
            for r in range(c + 1, nK):
                a = D[r * lK + c]
                for cc in range(lJ):
                    X[r * lJ + cc] -= a * X[c * lJ + cc]
        for q in range(Lp[K], Lp[K + 1]):       # X_IJ -= L_IK U_KJ
            nI = bsz[Li[q]]
            Lb = S[Loff[q]: Loff[q] + nI * lK]
            y0 = where[Li[q]]
            Y = S[y0: y0 + nI * lJ]
            for r in range(nI):
                for k in range(nK):
                    a = Lb[r * lK + k]
                    for cc in range(lJ):
                        Y[r * lJ + cc] -= a * X[k * lJ + cc]
    # ---- panel: diagonal block with the blocks below, pivots inside the diagonal block
    D = S[Doff[J]: Doff[J] + nJ * lJ]
    q0 = pstart[J]
    for c in range(nJ):
        r_best = c
        a_best = abs(D[c * lJ + c])
        for r in range(c + 1, nJ):
            a = abs(D[r * lJ + c])
            if a > a_best:
                a_best = a
                r_best = r
        a_below = 0.0
        for p in range(Lp[J], Lp[J + 1]):
            l0 = Loff[p]
            for r in range(bsz[Li[p]]):
                a = abs(S[l0 + r * lJ + c])
                if a > a_below:
                    a_below = a
        if not (a_best > 0.0) or not math.isfinite(a_best) or a_best < threshold * a_below:
            return False
        piv[q0 + c] = r_best
        if r_best != c:
            for cc in range(lJ):
                t = D[c * lJ + cc]
                D[c * lJ + cc] = D[r_best * lJ + cc]
                D[r_best * lJ + cc] = t
        inv = 1.0 / D[c * lJ + c]
        for cc in range(c + 1):
            urow[cc] = 0.0
        for cc in range(c + 1, lJ):
            urow[cc] = D[c * lJ + cc]
        for r in range(c + 1, nJ):
            a = D[r * lJ + c] * inv
            for cc in range(lJ):
                D[r * lJ + cc] -= a * urow[cc]
            D[r * lJ + c] = a
        for p in range(Lp[J], Lp[J + 1]):
            nI = bsz[Li[p]]
            Lb = S[Loff[p]: Loff[p] + nI * lJ]
            for r in range(nI):
                a = Lb[r * lJ + c] * inv
                for cc in range(lJ):
                    Lb[r * lJ + cc] -= a * urow[cc]
                Lb[r * lJ + c] = a
    return True


@njit(cache=True, nogil=True)
def _block_numeric(data, amap, nB, bsz, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff, S, piv,
                   pstart, threshold, where, work, stats):  # pragma: no cover - compiled
    """Left-looking block LU in place in ``S``. Returns 0, or J + 1 if the pivot search of
    block column J fails (zero, not finite or below the threshold rule).

    ``stats`` (3) receives the largest |entry| of L, of U and of the matrix (the element
    growth of the factorisation, :attr:`BlockFactors.growth`); L is reported infinite if a
    block column went through the scalar loops (no growth measured there).

    Block (I, J) is stored by rows of ``ld[J]`` (``bsz[J]`` rounded up to a multiple of 4,
    the padding kept at zero). Block columns whose rows are 4, 8, 12 or 16 long (harmonic
    balance with H <= 7, and the border) go through :func:`_column_w`, whose rows are LLVM
    vectors; other lengths through the scalar loops of :func:`_column_any` (the same
    operations in the same order). ``where`` (nB) and ``work`` (at least ``m (m + 4)`` for
    m = max ld) are work arrays: the kernel allocates nothing, so loading its cached code
    needs none of numba's array modules.
    """
    S[:] = 0.0
    a_max = 0.0
    for p in range(data.size):
        a = data[p]
        S[amap[p]] = a
        a = abs(a)
        if a > a_max:
            a_max = a
    stats[0] = 1.0          # the multipliers inside diagonal blocks (partial pivoting)
    stats[1] = 0.0
    stats[2] = a_max
    for i in range(nB):
        where[i] = -1
    m = 0
    for J in range(nB):
        m = max(m, ld[J])
    upad = work[: m * m]
    inv = work[m * m: m * m + m]
    amax = work[m * m + m: m * m + 2 * m]
    adiag = work[m * m + 2 * m: m * m + 3 * m]
    urow = work[m * m + 3 * m: m * m + 4 * m]
    for i in range(urow.size):
        urow[i] = 0.0
    for J in range(nB):
        nJ = bsz[J]
        lJ = ld[J]
        for p in range(Up[J], Up[J + 1]):
            where[Ui[p]] = Uoff[p]
        where[J] = Doff[J]
        for p in range(Lp[J], Lp[J + 1]):
            where[Li[p]] = Loff[p]
        if lJ == 12:
            ok = _column_w(12, J, nJ, S, bsz, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff, piv,
                           pstart, threshold, where, upad, inv, amax, adiag, stats)
        elif lJ == 4:
            ok = _column_w(4, J, nJ, S, bsz, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff, piv,
                           pstart, threshold, where, upad, inv, amax, adiag, stats)
        elif lJ == 8:
            ok = _column_w(8, J, nJ, S, bsz, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff, piv,
                           pstart, threshold, where, upad, inv, amax, adiag, stats)
        elif lJ == 16:
            ok = _column_w(16, J, nJ, S, bsz, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff, piv,
                           pstart, threshold, where, upad, inv, amax, adiag, stats)
        else:
            ok = _column_any(J, nJ, lJ, S, bsz, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff, piv,
                             pstart, threshold, where, urow)
            stats[0] = np.inf
        _clear(where, Lp, Li, Up, Ui, J)
        if not ok:
            return J + 1
    return 0


#: Work entries after the n of the solve's right-hand sides: the vector loads of a block of
#: z may read up to 15 entries beyond it (masked to zero).
_SOLVE_PAD = 16


@intrinsic
def _row_dots(typingctx, width, S, o, rows, z, w, src, n, dst):  # pragma: no cover
    """For r < rows: ``z[dst + r] -= S[o + rW: o + rW + W] . z[src: src + n]`` and the same
    with w (n <= W; the lanes from n on are taken as zero): the block of each right-hand
    side is held in registers while the stored rows of W pass by. Products summed lane by
    lane over the W / 4 vectors, then across the four lanes."""
    W = _literal(width, "the row width")
    ip = types.intp
    sig = types.void(width, S, ip, ip, z, w, ip, ip, ip)

    def codegen(context, builder, signature, args):
        _, sa, o, rows, za, wa, src, n, dst = args
        ss = _data(context, builder, signature.args[1], sa)
        zs = _data(context, builder, signature.args[4], za)
        ws = _data(context, builder, signature.args[5], wa)
        i64v = ir.VectorType(n.type, 4)
        nv = builder.shuffle_vector(
            builder.insert_element(ir.Constant(i64v, None), n, ir.Constant(_I32, 0)),
            ir.Constant(i64v, None), ir.Constant(ir.VectorType(_I32, 4), [0, 0, 0, 0]))
        zero = ir.Constant(_V4, [0.0] * 4)
        blocks = []
        for vec in (zs, ws):
            regs = []
            for g in range(W // 4):
                mask = builder.icmp_signed("<", ir.Constant(i64v, [4 * g + i for i in range(4)]),
                                           nv)
                regs.append(builder.select(mask, _vload(builder, vec, _offset(builder, src,
                                                                               4 * g)), zero))
            blocks.append(regs)
        with cgutils.for_range(builder, rows) as loop:
            base = builder.add(o, builder.mul(loop.index, ir.Constant(o.type, W)))
            row = [_vload(builder, ss, _offset(builder, base, 4 * g)) for g in range(W // 4)]
            at = builder.add(dst, loop.index)
            for vec, regs in zip((zs, ws), blocks, strict=True):
                acc = builder.fmul(row[0], regs[0])
                for g in range(1, W // 4):
                    acc = builder.fadd(acc, builder.fmul(row[g], regs[g]))
                lane = [builder.extract_element(acc, ir.Constant(_I32, i)) for i in range(4)]
                dot = builder.fadd(builder.fadd(lane[0], lane[1]),
                                   builder.fadd(lane[2], lane[3]))
                ptr = _at(builder, vec, at)
                builder.store(builder.fsub(builder.load(ptr), dot), ptr)
        return context.get_dummy_value()

    return sig, codegen


@njit(cache=True, nogil=True, inline="always")
def _sub_block_products(S, o, ld_row, rows, z, w, src, n, dst):  # pragma: no cover
    """``z[dst: dst + rows] -= B z[src: src + n]`` and the same with w, B the block stored
    at ``S[o:]`` by rows of ``ld_row``: rows of 4, 8, 12 or 16 through :func:`_row_dots`,
    others by scalar loops."""
    if ld_row == 12:
        _row_dots(12, S, o, rows, z, w, src, n, dst)
    elif ld_row == 4:
        _row_dots(4, S, o, rows, z, w, src, n, dst)
    elif ld_row == 8:
        _row_dots(8, S, o, rows, z, w, src, n, dst)
    elif ld_row == 16:
        _row_dots(16, S, o, rows, z, w, src, n, dst)
    else:
        for r in range(rows):
            acc = 0.0
            acw = 0.0
            for k in range(n):
                a = S[o + r * ld_row + k]
                acc += a * z[src + k]
                acw += a * w[src + k]
            z[dst + r] -= acc
            w[dst + r] -= acw


@njit(cache=True, nogil=True)
def _block_solve2(b, c, out_b, out_c, sperm, nB, bsz, ld, bnew, Lp, Li, Up, Ui, Loff, Uoff,
                  Doff, S, piv, pstart, z, w):  # pragma: no cover - compiled
    """``out_b = A^-1 b`` and ``out_c = A^-1 c`` from the factors of :func:`_block_numeric`
    in one sweep over the factors (``z``, ``w``: n + :data:`_SOLVE_PAD` work entries each):
    for factors larger than the cache (ring of 480 contacts: 2.7 MB) the second right-hand
    side costs a fraction of a solve. The products with the off-diagonal blocks hold the
    block of each right-hand side in registers (:func:`_sub_block_products`), their sums
    ordered as a vector unit does them (as any LU solve may: the same residuals)."""
    n = sperm.size
    for i in range(n):
        z[i] = b[sperm[i]]
        w[i] = c[sperm[i]]
    for K in range(nB):                 # forward: P, unit L
        nK = bsz[K]
        lK = ld[K]
        s0 = bnew[K]
        d0 = Doff[K]
        q0 = pstart[K]
        for cc in range(nK):
            r = piv[q0 + cc]
            if r != cc:
                t = z[s0 + cc]
                z[s0 + cc] = z[s0 + r]
                z[s0 + r] = t
                t = w[s0 + cc]
                w[s0 + cc] = w[s0 + r]
                w[s0 + r] = t
        for cc in range(nK):
            zc = z[s0 + cc]
            wc = w[s0 + cc]
            for r in range(cc + 1, nK):
                a = S[d0 + r * lK + cc]
                z[s0 + r] -= a * zc
                w[s0 + r] -= a * wc
        for q in range(Lp[K], Lp[K + 1]):
            I = Li[q]
            _sub_block_products(S, Loff[q], lK, bsz[I], z, w, s0, nK, bnew[I])
    for J in range(nB - 1, -1, -1):     # backward: U
        nJ = bsz[J]
        lJ = ld[J]
        s0 = bnew[J]
        d0 = Doff[J]
        for cr in range(nJ - 1, -1, -1):
            acc = z[s0 + cr]
            acw = w[s0 + cr]
            for cc in range(cr + 1, nJ):
                a = S[d0 + cr * lJ + cc]
                acc -= a * z[s0 + cc]
                acw -= a * w[s0 + cc]
            dg = S[d0 + cr * lJ + cr]
            z[s0 + cr] = acc / dg
            w[s0 + cr] = acw / dg
        for p in range(Up[J], Up[J + 1]):
            K = Ui[p]
            _sub_block_products(S, Uoff[p], lJ, bsz[K], z, w, s0, nJ, bnew[K])
    for i in range(n):
        out_b[sperm[i]] = z[i]
        out_c[sperm[i]] = w[i]
