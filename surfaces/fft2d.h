#pragma once
// A small RAII wrapper over FFTW's 2-D real transforms (double precision), shared by the
// synthesis and the statistics. FFTW's planner is not thread-safe, so plan creation and
// destruction are serialised by a mutex; executing a plan is thread-safe.
#include <complex>
#include <cstddef>

namespace littoral::surfaces {

class Fft2dReal {
public:
    // Real array of ny rows x nx columns (row-major), spectrum of ny x (nx/2 + 1).
    Fft2dReal(int nx, int ny);
    ~Fft2dReal();
    Fft2dReal(const Fft2dReal&) = delete;
    Fft2dReal& operator=(const Fft2dReal&) = delete;

    int nx() const { return nx_; }
    int ny() const { return ny_; }
    int halfX() const { return nx_ / 2 + 1; }
    double* real() { return real_; }
    std::complex<double>* spectrum() { return spec_; }
    // Unnormalised transforms: forward X_k = Sum_x f_x e^{-i k.x}, backward f_x = Sum_k X_k e^{+i k.x}.
    // The backward transform overwrites the spectrum (FFTW c2r semantics).
    void forward();
    void backward();

    // Bytes needed for an (nx x ny) transform, for memory estimates.
    static size_t bytesFor(int nx, int ny);

private:
    int nx_, ny_;
    double* real_ = nullptr;
    std::complex<double>* spec_ = nullptr;
    void* planForward_ = nullptr;
    void* planBackward_ = nullptr;
};

}  // namespace littoral::surfaces
