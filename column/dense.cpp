#include "column/dense.h"

#include <cmath>
#include <utility>

#include "core/error.h"

namespace littoral::column {

Matrix Matrix::identity(int n) {
    Matrix m(n, n);
    for (int i = 0; i < n; ++i) m(i, i) = 1.0;
    return m;
}

Matrix Matrix::diagonal(const std::vector<double>& d) {
    const int n = static_cast<int>(d.size());
    Matrix m(n, n);
    for (int i = 0; i < n; ++i) m(i, i) = d[static_cast<size_t>(i)];
    return m;
}

double Matrix::maxAbs() const {
    double m = 0;
    for (double v : a_) m = std::max(m, std::abs(v));
    return m;
}

Matrix Matrix::operator*(const Matrix& b) const {
    LITTORAL_CHECK_EQ(c_, b.r_);
    Matrix p(r_, b.c_);
    for (int i = 0; i < r_; ++i)
        for (int k = 0; k < c_; ++k) {
            const double aik = (*this)(i, k);
            if (aik == 0.0) continue;
            for (int j = 0; j < b.c_; ++j) p(i, j) += aik * b(k, j);
        }
    return p;
}

Matrix Matrix::operator+(const Matrix& b) const {
    LITTORAL_CHECK(r_ == b.r_ && c_ == b.c_);
    Matrix s = *this;
    for (size_t i = 0; i < a_.size(); ++i) s.a_[i] += b.a_[i];
    return s;
}

Matrix Matrix::operator-(const Matrix& b) const {
    LITTORAL_CHECK(r_ == b.r_ && c_ == b.c_);
    Matrix s = *this;
    for (size_t i = 0; i < a_.size(); ++i) s.a_[i] -= b.a_[i];
    return s;
}

std::vector<double> Matrix::operator*(const std::vector<double>& x) const {
    LITTORAL_CHECK_EQ(static_cast<size_t>(c_), x.size());
    std::vector<double> y(static_cast<size_t>(r_), 0.0);
    for (int i = 0; i < r_; ++i) {
        double s = 0;
        for (int j = 0; j < c_; ++j) s += (*this)(i, j) * x[static_cast<size_t>(j)];
        y[static_cast<size_t>(i)] = s;
    }
    return y;
}

std::vector<double> operator+(const std::vector<double>& a, const std::vector<double>& b) {
    LITTORAL_CHECK_EQ(a.size(), b.size());
    std::vector<double> s = a;
    for (size_t i = 0; i < a.size(); ++i) s[i] += b[i];
    return s;
}

std::vector<double> operator*(double s, const std::vector<double>& a) {
    std::vector<double> p = a;
    for (double& v : p) v *= s;
    return p;
}

Matrix solve(const Matrix& a, const Matrix& b) {
    const int n = a.rows();
    LITTORAL_CHECK_EQ(n, a.cols());
    LITTORAL_CHECK_EQ(n, b.rows());
    Matrix lu = a, x = b;
    const double scale = std::max(a.maxAbs(), 1e-300);
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i)
            if (std::abs(lu(i, k)) > std::abs(lu(p, k))) p = i;
        if (std::abs(lu(p, k)) < 1e-14 * scale) LITTORAL_CHECK(!"column::solve: singular matrix");
        if (p != k) {
            for (int j = 0; j < n; ++j) std::swap(lu(k, j), lu(p, j));
            for (int j = 0; j < x.cols(); ++j) std::swap(x(k, j), x(p, j));
        }
        for (int i = k + 1; i < n; ++i) {
            const double f = lu(i, k) / lu(k, k);
            if (f == 0.0) continue;
            for (int j = k + 1; j < n; ++j) lu(i, j) -= f * lu(k, j);
            for (int j = 0; j < x.cols(); ++j) x(i, j) -= f * x(k, j);
        }
    }
    for (int k = n - 1; k >= 0; --k)
        for (int j = 0; j < x.cols(); ++j) {
            double s = x(k, j);
            for (int i = k + 1; i < n; ++i) s -= lu(k, i) * x(i, j);
            x(k, j) = s / lu(k, k);
        }
    return x;
}

std::vector<double> solve(const Matrix& a, const std::vector<double>& b) {
    Matrix bm(static_cast<int>(b.size()), 1);
    for (size_t i = 0; i < b.size(); ++i) bm(static_cast<int>(i), 0) = b[i];
    const Matrix x = solve(a, bm);
    std::vector<double> r(b.size());
    for (size_t i = 0; i < b.size(); ++i) r[i] = x(static_cast<int>(i), 0);
    return r;
}

}  // namespace littoral::column
