#include "surfaces/fft2d.h"

#include <mutex>
#include <new>

#include <fftw3.h>

#include "core/error.h"

namespace littoral::surfaces {

namespace {
std::mutex& plannerMutex() {
    static std::mutex m;
    return m;
}
}  // namespace

size_t Fft2dReal::bytesFor(int nx, int ny) {
    return static_cast<size_t>(nx) * ny * sizeof(double) +
           static_cast<size_t>(nx / 2 + 1) * ny * sizeof(fftw_complex);
}

Fft2dReal::Fft2dReal(int nx, int ny) : nx_(nx), ny_(ny) {
    LITTORAL_CHECK_GT(nx, 0);
    LITTORAL_CHECK_GT(ny, 0);
    const size_t nReal = static_cast<size_t>(nx) * ny;
    const size_t nSpec = static_cast<size_t>(nx / 2 + 1) * ny;
    real_ = static_cast<double*>(fftw_malloc(nReal * sizeof(double)));
    spec_ = reinterpret_cast<std::complex<double>*>(fftw_malloc(nSpec * sizeof(fftw_complex)));
    if (!real_ || !spec_) {
        fftw_free(real_);
        fftw_free(spec_);
        throw std::bad_alloc();
    }
    std::lock_guard<std::mutex> lock(plannerMutex());
    // FFTW_ESTIMATE: no trial runs, so planning never touches (or overwrites) the arrays.
    planForward_ = fftw_plan_dft_r2c_2d(ny, nx, real_, reinterpret_cast<fftw_complex*>(spec_), FFTW_ESTIMATE);
    planBackward_ = fftw_plan_dft_c2r_2d(ny, nx, reinterpret_cast<fftw_complex*>(spec_), real_, FFTW_ESTIMATE);
    LITTORAL_CHECK(planForward_ != nullptr && planBackward_ != nullptr);
}

Fft2dReal::~Fft2dReal() {
    {
        std::lock_guard<std::mutex> lock(plannerMutex());
        if (planForward_) fftw_destroy_plan(static_cast<fftw_plan>(planForward_));
        if (planBackward_) fftw_destroy_plan(static_cast<fftw_plan>(planBackward_));
    }
    fftw_free(real_);
    fftw_free(spec_);
}

void Fft2dReal::forward() { fftw_execute(static_cast<fftw_plan>(planForward_)); }
void Fft2dReal::backward() { fftw_execute(static_cast<fftw_plan>(planBackward_)); }

}  // namespace littoral::surfaces
