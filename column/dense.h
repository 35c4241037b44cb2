#pragma once
// Small dense real matrices for the column solver's operators (a few tens of rows): row-major
// storage, products, and the solution of A X = B by LU decomposition with partial pivoting.
// The adding-doubling method needs nothing more, so the module needs no linear-algebra library.
#include <cstddef>
#include <vector>

namespace littoral::column {

class Matrix {
public:
    Matrix() = default;
    Matrix(int rows, int cols) : r_(rows), c_(cols), a_(static_cast<size_t>(rows) * static_cast<size_t>(cols), 0.0) {}
    static Matrix identity(int n);
    static Matrix diagonal(const std::vector<double>& d);

    int rows() const { return r_; }
    int cols() const { return c_; }
    double& operator()(int i, int j) { return a_[static_cast<size_t>(i) * static_cast<size_t>(c_) + static_cast<size_t>(j)]; }
    double operator()(int i, int j) const {
        return a_[static_cast<size_t>(i) * static_cast<size_t>(c_) + static_cast<size_t>(j)];
    }
    double maxAbs() const;

    Matrix operator*(const Matrix& b) const;
    Matrix operator+(const Matrix& b) const;
    Matrix operator-(const Matrix& b) const;
    std::vector<double> operator*(const std::vector<double>& x) const;

private:
    int r_ = 0, c_ = 0;
    std::vector<double> a_;
};

std::vector<double> operator+(const std::vector<double>& a, const std::vector<double>& b);
std::vector<double> operator*(double s, const std::vector<double>& a);

// X with A X = B (A square, nonsingular). Throws InternalError if A is singular to working precision.
Matrix solve(const Matrix& a, const Matrix& b);
std::vector<double> solve(const Matrix& a, const std::vector<double>& b);

}  // namespace littoral::column
