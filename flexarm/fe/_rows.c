/* Row-by-row assembly of straight-sided tet meshes into CSR (see flexarm/fe/rows.py).
 *
 * Each node row of the global matrices is built in one go: the elements around the node
 * give their row blocks, which are added into the row while it sits in the L1 cache, and
 * the row is written once, in order.  No element matrix, slot array or block matrix is
 * ever stored, so memory traffic is close to writing the CSR arrays once.
 *
 * Arrays come in through the buffer protocol (C-contiguous, allocated by NumPy on the
 * Python side); no NumPy headers are needed to build this file.  Index types: element
 * nodes and node-level pointers int64, CSR indices and pointers int32 (the caller checks
 * that 9 nnz fits).  Every sum runs in a fixed order: the result is deterministic.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define MAX_NN 10 /* Tet10 */
#define MAX_NQ 8  /* points of the stiffness rule */

typedef struct { Py_buffer b; int ok; } buf_t;

static void release(buf_t *bufs, int n) {
    for (int i = 0; i < n; i++) if (bufs[i].ok) PyBuffer_Release(&bufs[i].b);
}

/* Take buffer i of args as contiguous, writable if asked, of at least `bytes` bytes. */
static int take(PyObject *obj, buf_t *out, int writable, Py_ssize_t bytes, const char *name) {
    int flags = PyBUF_C_CONTIGUOUS | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, &out->b, flags) < 0) return -1;
    out->ok = 1;
    if (out->b.len < bytes) {
        PyErr_Format(PyExc_ValueError, "%s: %zd bytes, expected at least %zd", name,
                     out->b.len, bytes);
        return -1;
    }
    return 0;
}

/* Corner map of element e: returns det J and fills P = J^-1 (rows are cofactor vectors
 * over det, P[3k + i] = d xi_k / d x_i), the formula of kernels._affine_inverse. */
static inline double corner_inverse(const double *pts, const int64_t *t, double *P) {
    const double *x0 = pts + 3 * t[0];
    double a[3][3];
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) a[j][i] = pts[3 * t[j + 1] + i] - x0[i];
    double c[3][3];
    for (int k = 0; k < 3; k++) {
        const double *u = a[(k + 1) % 3], *v = a[(k + 2) % 3];
        c[k][0] = u[1] * v[2] - u[2] * v[1];
        c[k][1] = u[2] * v[0] - u[0] * v[2];
        c[k][2] = u[0] * v[1] - u[1] * v[0];
    }
    double det = a[0][0] * c[0][0] + a[0][1] * c[0][1] + a[0][2] * c[0][2];
    if (P) {
        const double inv = 1.0 / det;
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++) P[3 * k + i] = c[k][i] * inv;
    }
    return det;
}

/* corner_det(points, tets, nn, det_out): det J of every element's corner map. */
static PyObject *corner_det(PyObject *self, PyObject *args) {
    PyObject *o[3]; Py_ssize_t nn;
    if (!PyArg_ParseTuple(args, "OOnO", &o[0], &o[1], &nn, &o[2])) return NULL;
    buf_t b[3];
    memset(b, 0, sizeof b);
    if (take(o[0], &b[0], 0, 0, "points") || take(o[1], &b[1], 0, 0, "tets")) goto fail;
    Py_ssize_t n_e = b[1].b.len / (Py_ssize_t)sizeof(int64_t) / nn;
    if (take(o[2], &b[2], 1, n_e * (Py_ssize_t)sizeof(double), "det")) goto fail;
    const double *pts = b[0].b.buf; const int64_t *tets = b[1].b.buf; double *det = b[2].b.buf;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t e = 0; e < n_e; e++) det[e] = corner_inverse(pts, tets + e * nn, NULL);
    Py_END_ALLOW_THREADS
    release(b, 3);
    Py_RETURN_NONE;
fail:
    release(b, 3);
    return NULL;
}

/* midside_deviation(points, tets10, edges (6, 2) int64) -> (max |mid - edge centre|,
 * max |corner difference|): how far a Tet10 mesh is from straight-sided. */
static PyObject *midside_deviation(PyObject *self, PyObject *args) {
    PyObject *o[3];
    if (!PyArg_ParseTuple(args, "OOO", &o[0], &o[1], &o[2])) return NULL;
    buf_t b[3];
    memset(b, 0, sizeof b);
    if (take(o[0], &b[0], 0, 0, "points") || take(o[1], &b[1], 0, 0, "tets")
        || take(o[2], &b[2], 0, 12 * sizeof(int64_t), "edges")) goto fail;
    const double *pts = b[0].b.buf; const int64_t *tets = b[1].b.buf, *ed = b[2].b.buf;
    Py_ssize_t n_e = b[1].b.len / (Py_ssize_t)sizeof(int64_t) / 10;
    double dev = 0.0, scale = 0.0;
    for (Py_ssize_t e = 0; e < n_e; e++) {
        const int64_t *t = tets + 10 * e;
        for (int k = 0; k < 6; k++) {
            const double *p = pts + 3 * t[ed[2 * k]], *q = pts + 3 * t[ed[2 * k + 1]];
            const double *m = pts + 3 * t[4 + k];
            for (int i = 0; i < 3; i++) {
                double d = m[i] - 0.5 * (p[i] + q[i]), s = p[i] - q[i];
                d = d < 0 ? -d : d; s = s < 0 ? -s : s;
                if (d > dev || d != d) dev = d;  /* NaN wins: not straight */
                if (s > scale) scale = s;
            }
        }
    }
    release(b, 3);
    return Py_BuildValue("dd", dev, scale);
fail:
    release(b, 3);
    return NULL;
}

/* node_rows(tets, nn, n_nodes, occ_ptr (n+1) i64, occ (m nn) i64, indptr (n+1) i64) -> nnz
 *
 * Groups the element nodes by node (a stable counting sort: occ lists e*nn + a in
 * element order) and counts the distinct neighbours of every node (indptr). */
static PyObject *node_rows(PyObject *self, PyObject *args) {
    PyObject *o[4]; Py_ssize_t nn, n;
    if (!PyArg_ParseTuple(args, "OnnOOO", &o[0], &nn, &n, &o[1], &o[2], &o[3])) return NULL;
    buf_t b[4];
    memset(b, 0, sizeof b);
    if (take(o[0], &b[0], 0, 0, "tets")) goto fail;
    Py_ssize_t n_occ = b[0].b.len / (Py_ssize_t)sizeof(int64_t);
    if (take(o[1], &b[1], 1, (n + 1) * 8, "occ_ptr") || take(o[2], &b[2], 1, n_occ * 8, "occ")
        || take(o[3], &b[3], 1, (n + 1) * 8, "indptr")) goto fail;
    const int64_t *tets = b[0].b.buf;
    int64_t *ptr = b[1].b.buf, *occ = b[2].b.buf, *indptr = b[3].b.buf;
    int32_t *mark = malloc((size_t)(n > 0 ? n : 1) * sizeof(int64_t));
    if (!mark) { PyErr_NoMemory(); goto fail; }
    Py_BEGIN_ALLOW_THREADS
    memset(ptr, 0, (size_t)(n + 1) * sizeof(int64_t));
    for (Py_ssize_t k = 0; k < n_occ; k++) ptr[tets[k] + 1]++;
    for (Py_ssize_t r = 0; r < n; r++) ptr[r + 1] += ptr[r];
    int64_t *next = (int64_t *)mark;  /* next free place of each row, then stamps */
    for (Py_ssize_t r = 0; r < n; r++) next[r] = ptr[r];
    for (Py_ssize_t k = 0; k < n_occ; k++) occ[next[tets[k]]++] = k;
    for (Py_ssize_t r = 0; r < n; r++) mark[r] = -1;
    indptr[0] = 0;
    for (Py_ssize_t r = 0; r < n; r++) {
        int64_t len = 0;
        for (int64_t q = ptr[r]; q < ptr[r + 1]; q++) {
            const int64_t *t = tets + (occ[q] / nn) * nn;
            for (Py_ssize_t j = 0; j < nn; j++)
                if (mark[t[j]] != (int32_t)r) { mark[t[j]] = (int32_t)r; len++; }
        }
        indptr[r + 1] = indptr[r] + len;
    }
    Py_END_ALLOW_THREADS
    free(mark);
    int64_t nnz = indptr[n];
    release(b, 4);
    return PyLong_FromLongLong(nnz);
fail:
    release(b, 4);
    return NULL;
}

/* node_columns(tets, nn, occ_ptr, occ, indptr, indices (nnz) i32): the sorted distinct
 * neighbours of every node (the node graph's CSR column indices). */
static PyObject *node_columns(PyObject *self, PyObject *args) {
    PyObject *o[5]; Py_ssize_t nn;
    if (!PyArg_ParseTuple(args, "OnOOOO", &o[0], &nn, &o[1], &o[2], &o[3], &o[4])) return NULL;
    buf_t b[5];
    memset(b, 0, sizeof b);
    if (take(o[0], &b[0], 0, 0, "tets") || take(o[1], &b[1], 0, 8, "occ_ptr")
        || take(o[2], &b[2], 0, 0, "occ") || take(o[3], &b[3], 0, 8, "indptr")) goto fail;
    Py_ssize_t n = b[1].b.len / 8 - 1;
    const int64_t *tets = b[0].b.buf, *ptr = b[1].b.buf, *occ = b[2].b.buf, *indptr = b[3].b.buf;
    if (take(o[4], &b[4], 1, indptr[n] * 4, "indices")) goto fail;
    int32_t *ind = b[4].b.buf;
    int32_t *mark = malloc((size_t)(n > 0 ? n : 1) * sizeof(int64_t));
    if (!mark) { PyErr_NoMemory(); goto fail; }
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t r = 0; r < n; r++) mark[r] = -1;
    for (Py_ssize_t r = 0; r < n; r++) {
        int32_t *row = ind + indptr[r];
        int64_t len = 0;
        for (int64_t q = ptr[r]; q < ptr[r + 1]; q++) {
            const int64_t *t = tets + (occ[q] / nn) * nn;
            for (Py_ssize_t j = 0; j < nn; j++)
                if (mark[t[j]] != (int32_t)r) { mark[t[j]] = (int32_t)r; row[len++] = (int32_t)t[j]; }
        }
        for (int64_t i = 1; i < len; i++) {  /* rows are short: insertion sort */
            int32_t v = row[i]; int64_t j = i - 1;
            while (j >= 0 && row[j] > v) { row[j + 1] = row[j]; j--; }
            row[j + 1] = v;
        }
    }
    Py_END_ALLOW_THREADS
    free(mark);
    release(b, 5);
    Py_RETURN_NONE;
fail:
    release(b, 5);
    return NULL;
}

/* The rows of K and M (see fill); nn and nq are constants at each call site. */
static inline __attribute__((always_inline)) void fill_rows(
    const Py_ssize_t nn, const Py_ssize_t nq, const Py_ssize_t n, const double lam,
    const double mu, const double *pts, const double *dN, const double *w, const double *mass,
    const int64_t *tets, const int64_t *ptr, const int64_t *occ, const int64_t *indptr,
    const int32_t *ind, int32_t *pos, double *kd, int32_t *ki, int32_t *kp, double *md,
    int32_t *mi, int32_t *mp) {
    for (Py_ssize_t r = 0; r < n; r++) {
        const int64_t start = indptr[r], L = indptr[r + 1] - start;
        for (int64_t p = 0; p < L; p++) pos[ind[start + p]] = (int32_t)p;
        double *K = kd ? kd + 9 * start : NULL, *M = md ? md + 3 * start : NULL;
        if (K) {
            memset(K, 0, (size_t)(9 * L) * sizeof(double));
            for (int i = 0; i < 3; i++) {
                kp[3 * r + i] = (int32_t)(9 * start + 3 * i * L);
                int32_t *row = ki + 9 * start + 3 * i * L;
                for (int64_t p = 0; p < L; p++)
                    for (int j = 0; j < 3; j++) row[3 * p + j] = 3 * ind[start + p] + j;
            }
        }
        if (M) {
            memset(M, 0, (size_t)(3 * L) * sizeof(double));
            for (int i = 0; i < 3; i++) {
                mp[3 * r + i] = (int32_t)(3 * start + i * L);
                int32_t *row = mi + 3 * start + i * L;
                for (int64_t p = 0; p < L; p++) row[p] = 3 * ind[start + p] + i;
            }
        }
        for (int64_t q = ptr[r]; q < ptr[r + 1]; q++) {
            const int64_t e = occ[q] / nn, a = occ[q] % nn;
            const int64_t *t = tets + e * nn;
            double P[9];
            const double d = corner_inverse(pts, t, P);
            if (K) {
                /* g[b][s][i]: physical gradient of node b at point s; ga = w_s d g_a */
                double g[MAX_NN][MAX_NQ][3], ga[MAX_NQ][3];
                for (Py_ssize_t bb = 0; bb < nn; bb++)
                    for (Py_ssize_t s = 0; s < nq; s++) {
                        const double *r0 = dN + 3 * (s * nn + bb);
                        for (int i = 0; i < 3; i++)
                            g[bb][s][i] = P[i] * r0[0] + P[3 + i] * r0[1] + P[6 + i] * r0[2];
                    }
                for (Py_ssize_t s = 0; s < nq; s++)
                    for (int i = 0; i < 3; i++) ga[s][i] = w[s] * d * g[a][s][i];
                for (Py_ssize_t bb = 0; bb < nn; bb++) {
                    double E[9] = {0};
                    for (Py_ssize_t s = 0; s < nq; s++)
                        for (int i = 0; i < 3; i++)
                            for (int j = 0; j < 3; j++) E[3 * i + j] += ga[s][i] * g[bb][s][j];
                    const double tr = mu * (E[0] + E[4] + E[8]);
                    double *out = K + 3 * pos[t[bb]];
                    for (int i = 0; i < 3; i++)
                        for (int j = 0; j < 3; j++)
                            out[3 * i * L + j] += lam * E[3 * i + j] + mu * E[3 * j + i]
                                                  + (i == j ? tr : 0.0);
                }
            }
            if (M)
                for (Py_ssize_t bb = 0; bb < nn; bb++) {
                    const int32_t p = pos[t[bb]];
                    const double m = mass[a * nn + bb] * d;
                    M[p] += m; M[L + p] += m; M[2 * L + p] += m;
                }
        }
    }
}

/* fill(points, tets, nn, occ_ptr, occ, indptr, indices, grads, weights, lam, mu, mass,
 *      K_data, K_indices, K_indptr, M_data, M_indices, M_indptr)
 *
 * For straight-sided elements with P = J^-1 and d = det J, the physical gradients at the
 * reference quadrature points are g_a(q) = P^T grads[q, a] and
 *   E_ab = sum_q weights[q] g_a(q) g_b(q)^T,
 *   K_ab = d (lam E_ab + mu E_ab^T + mu tr(E_ab) I),
 * exact when the rule integrates dN_a . dN_b exactly; the scalar mass is M_ab = mass_ab d
 * (mass: the reference integrals of N_a N_b times rho).  K or M is skipped when its data
 * buffer is None.  DOF row 3r + i of K holds columns 3c + j, of M columns 3c + i, for the
 * node columns c of row r in order. */
static PyObject *fill(PyObject *self, PyObject *args) {
    PyObject *o[15]; Py_ssize_t nn; double lam, mu;
    if (!PyArg_ParseTuple(args, "OOnOOOOOOddOOOOOOO", &o[0], &o[1], &nn, &o[2], &o[3], &o[4],
                          &o[5], &o[6], &o[7], &lam, &mu, &o[8], &o[9], &o[10], &o[11], &o[12],
                          &o[13], &o[14]))
        return NULL;
    buf_t b[15];
    memset(b, 0, sizeof b);
    if (nn > MAX_NN) { PyErr_SetString(PyExc_ValueError, "nn: at most 10 nodes"); return NULL; }
    if (take(o[0], &b[0], 0, 0, "points") || take(o[1], &b[1], 0, 0, "tets")
        || take(o[2], &b[2], 0, 8, "occ_ptr") || take(o[3], &b[3], 0, 0, "occ")
        || take(o[4], &b[4], 0, 8, "indptr") || take(o[7], &b[7], 0, 8, "weights")) goto fail;
    Py_ssize_t n = b[2].b.len / 8 - 1, nq = b[7].b.len / 8;
    if (nq > MAX_NQ) { PyErr_SetString(PyExc_ValueError, "weights: at most 8 points"); goto fail; }
    const int64_t *indptr = b[4].b.buf;
    int64_t nnz = indptr[n];
    if (take(o[5], &b[5], 0, nnz * 4, "indices")
        || take(o[6], &b[6], 0, nq * nn * 24, "grads")
        || take(o[8], &b[8], 0, nn * nn * 8, "mass")) goto fail;
    int want_k = o[9] != Py_None, want_m = o[12] != Py_None;
    if (want_k && (take(o[9], &b[9], 1, 9 * nnz * 8, "K data")
                   || take(o[10], &b[10], 1, 9 * nnz * 4, "K indices")
                   || take(o[11], &b[11], 1, (3 * n + 1) * 4, "K indptr"))) goto fail;
    if (want_m && (take(o[12], &b[12], 1, 3 * nnz * 8, "M data")
                   || take(o[13], &b[13], 1, 3 * nnz * 4, "M indices")
                   || take(o[14], &b[14], 1, (3 * n + 1) * 4, "M indptr"))) goto fail;
    const double *pts = b[0].b.buf, *dN = b[6].b.buf, *w = b[7].b.buf, *mass = b[8].b.buf;
    const int64_t *tets = b[1].b.buf, *ptr = b[2].b.buf, *occ = b[3].b.buf;
    const int32_t *ind = b[5].b.buf;
    double *kd = want_k ? b[9].b.buf : NULL, *md = want_m ? b[12].b.buf : NULL;
    int32_t *ki = want_k ? b[10].b.buf : NULL, *kp = want_k ? b[11].b.buf : NULL;
    int32_t *mi = want_m ? b[13].b.buf : NULL, *mp = want_m ? b[14].b.buf : NULL;
    int32_t *pos = malloc((size_t)(n > 0 ? n : 1) * sizeof(int32_t));
    if (!pos) { PyErr_NoMemory(); goto fail; }
    Py_BEGIN_ALLOW_THREADS
    /* constant element sizes let the compiler unroll the small loops */
    if (nn == 4 && nq == 1)
        fill_rows(4, 1, n, lam, mu, pts, dN, w, mass, tets, ptr, occ, indptr, ind, pos, kd, ki, kp, md, mi, mp);
    else if (nn == 10 && nq == 4)
        fill_rows(10, 4, n, lam, mu, pts, dN, w, mass, tets, ptr, occ, indptr, ind, pos, kd, ki, kp, md, mi, mp);
    else
        fill_rows(nn, nq, n, lam, mu, pts, dN, w, mass, tets, ptr, occ, indptr, ind, pos, kd, ki, kp, md, mi, mp);
    if (kp) kp[3 * n] = (int32_t)(9 * nnz);
    if (mp) mp[3 * n] = (int32_t)(3 * nnz);
    Py_END_ALLOW_THREADS
    free(pos);
    release(b, 15);
    Py_RETURN_NONE;
fail:
    release(b, 15);
    return NULL;
}

static PyMethodDef methods[] = {
    {"corner_det", corner_det, METH_VARARGS, "det J of every element's corner map"},
    {"midside_deviation", midside_deviation, METH_VARARGS, "Tet10 mid-edge deviation"},
    {"node_rows", node_rows, METH_VARARGS, "occurrences by node and node-row lengths"},
    {"node_columns", node_columns, METH_VARARGS, "sorted node-graph columns"},
    {"fill", fill, METH_VARARGS, "K and M CSR arrays, row by row"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_rows", NULL, -1, methods};

/* Raised whenever a function's arguments change: rows.py ignores a stale build. */
#define API_VERSION 1

PyMODINIT_FUNC PyInit__rows(void) {
    PyObject *m = PyModule_Create(&module);
    if (m && PyModule_AddIntConstant(m, "API_VERSION", API_VERSION) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
