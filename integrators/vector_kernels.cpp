#include "integrators/vector_kernels.h"

#include <nvector/nvector_serial.h>

#include <cmath>

namespace kiln {

namespace {

double* data(N_Vector v) { return NV_DATA_S(v); }
sunindextype length(N_Vector v) { return NV_LENGTH_S(v); }

// a x + b y; with a = b (a = -b) as SUNDIALS does it, a (x + y) (a (x - y)): the same bits. Where
// a or b is 1 or -1 the general form gives SUNDIALS' bits too (1 x and -1 x are exact).
void linear_sum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  const sunindextype n = length(x);
  const bool unit = a == 1 || a == -1 || b == 1 || b == -1;
  if (!unit && a == b) {
    for (sunindextype k = 0; k < n; ++k) zd[k] = a * (xd[k] + yd[k]);
  } else if (!unit && a == -b) {
    for (sunindextype k = 0; k < n; ++k) zd[k] = a * (xd[k] - yd[k]);
  } else {
    for (sunindextype k = 0; k < n; ++k) zd[k] = a * xd[k] + b * yd[k];
  }
}

void constant(realtype c, N_Vector z) {
  double* zd = data(z);
  for (sunindextype k = 0, n = length(z); k < n; ++k) zd[k] = c;
}

void scale(realtype c, N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype k = 0, n = length(x); k < n; ++k) zd[k] = c * xd[k];
}

void absolute(N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype k = 0, n = length(x); k < n; ++k) zd[k] = std::abs(xd[k]);
}

void product(N_Vector x, N_Vector y, N_Vector z) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  for (sunindextype k = 0, n = length(x); k < n; ++k) zd[k] = xd[k] * yd[k];
}

void add_constant(N_Vector x, realtype b, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype k = 0, n = length(x); k < n; ++k) zd[k] = xd[k] + b;
}

void inverse(N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype k = 0, n = length(x); k < n; ++k) zd[k] = 1.0 / xd[k];
}

realtype weighted_square_sum(N_Vector x, N_Vector w) {
  const double *xd = data(x), *wd = data(w);
  double sum = 0;
  for (sunindextype k = 0, n = length(x); k < n; ++k) {
    const double p = xd[k] * wd[k];
    sum += p * p;
  }
  return sum;
}

realtype weighted_rms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w) / static_cast<double>(length(x)));
}

realtype max_norm(N_Vector x) {
  const double* xd = data(x);
  double m = 0;
  for (sunindextype k = 0, n = length(x); k < n; ++k) m = std::fmax(m, std::abs(xd[k]));
  return m;
}

// z = sum_i c_i X_i: c_0 X_0, then each further term added in order, as SUNDIALS' generic
// combination does with N_VScale and N_VLinearSum (z may be X_0 or X_1).
int linear_combination(int nv, realtype* c, N_Vector* X, N_Vector z) {
  double* zd = data(z);
  const sunindextype n = length(z);
  if (nv == 1) {
    scale(c[0], X[0], z);
    return 0;
  }
  const double* x0 = data(X[0]);
  const double* x1 = data(X[1]);
  for (sunindextype k = 0; k < n; ++k) zd[k] = c[0] * x0[k] + c[1] * x1[k];
  for (int i = 2; i < nv; ++i) {
    const double* xi = data(X[i]);
    for (sunindextype k = 0; k < n; ++k) zd[k] += c[i] * xi[k];
  }
  return 0;
}

// Z_i = a_i x + Y_i.
int scale_add_multi(int nv, realtype* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  const double* xd = data(x);
  const sunindextype n = length(x);
  for (int i = 0; i < nv; ++i) {
    const double* yd = data(Y[i]);
    double* zd = data(Z[i]);
    for (sunindextype k = 0; k < n; ++k) zd[k] = a[i] * xd[k] + yd[k];
  }
  return 0;
}

}  // namespace

void use_vector_kernels(N_Vector v) {
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = linear_sum;
  ops->nvconst = constant;
  ops->nvscale = scale;
  ops->nvabs = absolute;
  ops->nvprod = product;
  ops->nvaddconst = add_constant;
  ops->nvinv = inverse;
  ops->nvwrmsnorm = weighted_rms_norm;
  ops->nvwsqrsumlocal = weighted_square_sum;
  ops->nvmaxnorm = max_norm;
  ops->nvmaxnormlocal = max_norm;
  ops->nvlinearcombination = linear_combination;
  ops->nvscaleaddmulti = scale_add_multi;
}

}  // namespace kiln
