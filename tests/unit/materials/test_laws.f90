!> The material laws against closed forms and conservation properties (doc/theory.md §1):
!! - objectivity: St. Venant-Kirchhoff and neo-Hookean give sigma = 0 at F = R (any angle),
!!   and sigma(R F) = R sigma(F) R^T for every finite-strain law;
!! - hyperelasticity: the stress equals the derivative of the returned energy density,
!!   P = dW/dF by central differences (an independent check of stress and energy);
!! - the neo-Hookean small-strain limit is linear elasticity with mu = 2 C10, K = 2/D1;
!! - J2 in uniaxial strain (E = 1000, nu = 0.3, sigma_y = 5 + 100 epbar): elastic up to the
!!   Hugoniot elastic limit sigma_HEL = sigma_y (1 - nu)/(1 - 2 nu) = 8.75, then the plastic
!!   modulus K + 4/3 mu H/(3 mu + H); |sigma_xx| = 31.266 at eps = 0.03226 (the plateau of the
!!   plastic wave; 5 digits given, so 3e-4); the plastic work is int sigma_y d epbar.
program test_laws
  use ictus_core_kinds, only: dp, pi
  use ictus_materials_law, only: law_t, kinematics_t, ANALYSIS_PLANE_STRAIN, tensor_of
  use ictus_materials_material, only: material_make_law
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  class(law_t), allocatable :: svk, nh, j2s, j2f, lin
  type(kinematics_t), parameter :: finite = kinematics_t(ANALYSIS_PLANE_STRAIN, .true.), &
      small = kinematics_t(ANALYSIS_PLANE_STRAIN, .false.)
  call t%start("materials/laws")
  call material_make_law('LINEAR ELASTIC', [1000.0_dp, 0.3_dp], finite, svk)
  call material_make_law('NEO HOOKE', [25.0_dp, 0.02_dp], finite, nh)
  call material_make_law('J2', [1000.0_dp, 0.3_dp, 5.0_dp, 0.0_dp, 105.0_dp, 1.0_dp], small, j2s)
  call material_make_law('J2', [1000.0_dp, 0.3_dp, 5.0_dp, 0.0_dp, 105.0_dp, 1.0_dp], finite, j2f)
  call material_make_law('LINEAR ELASTIC', [1000.0_dp, 0.3_dp], small, lin)
  call case_rotation(t, svk, 'SVK')
  call case_rotation(t, nh, 'neo-Hookean')
  call case_energy(t, svk, 'SVK', 1.0e-7_dp)
  call case_energy(t, nh, 'neo-Hookean', 1.0e-7_dp)
  call case_energy(t, j2f, 'J2 finite, elastic branch', 1.0e-6_dp, 0.002_dp)
  call case_frame(t, svk, 'SVK')
  call case_frame(t, nh, 'neo-Hookean')
  call case_frame(t, j2f, 'J2 finite after yield')
  call case_nh_limit(t, nh, lin)
  call case_uniaxial(t, j2s, 'J2 small strain', 1.0e-10_dp)
  call case_uniaxial(t, j2f, 'J2 finite strain, small-strain limit', 2.0e-2_dp)
  call t%finish()

contains

  !> F = R(theta): Cauchy stress zero to round-off.
  subroutine case_rotation(t, law, tag)
    type(checker_t), intent(inout) :: t
    class(law_t), intent(in) :: law
    character(len=*), intent(in) :: tag
    real(dp) :: grad(3, 3), sig(6), w, h(0), h2(0), th, worst
    integer :: k
    worst = 0.0_dp
    do k = 1, 12
      th = 2.0_dp*pi*real(k, dp)/12.0_dp - 0.1_dp
      grad = rotation(th)
      grad(1, 1) = grad(1, 1) - 1.0_dp
      grad(2, 2) = grad(2, 2) - 1.0_dp
      grad(3, 3) = 0.0_dp
      call law%stress(grad, h, h2, sig, w)
      worst = max(worst, maxval(abs(sig)), abs(w))
    end do
    call t%close_abs(worst, 0.0_dp, 1.0e-12_dp*1000.0_dp, tag//': sigma = 0 and W = 0 at F = R')
  end subroutine case_rotation

  !> P = J sigma F^-T against the central differences of W (in-plane components).
  subroutine case_energy(t, law, tag, tol, scale)
    type(checker_t), intent(inout) :: t
    class(law_t), intent(in) :: law
    character(len=*), intent(in) :: tag
    real(dp), intent(in) :: tol
    real(dp), intent(in), optional :: scale
    real(dp) :: g(3, 3), gp(3, 3), sig(6), w, wp, wm, p(3, 3), pfd, s, hist(law%nhist)
    real(dp) :: hnew(law%nhist), f(3, 3), finv(2, 2), detf, err, ref
    real(dp), parameter :: h = 1.0e-6_dp
    integer :: i, j
    s = 1.0_dp
    if (present(scale)) s = scale
    g = 0.0_dp
    g(1:2, 1:2) = s*reshape([0.3_dp, -0.1_dp, 0.4_dp, -0.2_dp], [2, 2])
    hist = 0.0_dp
    call law%stress(g, hist, hnew, sig, w)
    f = g
    do i = 1, 3
      f(i, i) = f(i, i) + 1.0_dp
    end do
    detf = f(1, 1)*f(2, 2) - f(1, 2)*f(2, 1)
    finv = reshape([f(2, 2), -f(2, 1), -f(1, 2), f(1, 1)], [2, 2])/detf
    p = 0.0_dp
    p(1:2, 1:2) = detf*matmul(reshape([sig(1), sig(4), sig(4), sig(2)], [2, 2]), transpose(finv))
    err = 0.0_dp
    ref = maxval(abs(p))
    do j = 1, 2
      do i = 1, 2
        gp = g
        gp(i, j) = g(i, j) + h
        call law%stress(gp, hist, hnew, sig, wp)
        gp(i, j) = g(i, j) - h
        call law%stress(gp, hist, hnew, sig, wm)
        pfd = (wp - wm)/(2.0_dp*h)
        err = max(err, abs(pfd - p(i, j)))
      end do
    end do
    call t%close_abs(err, 0.0_dp, tol*ref, tag//': P = dW/dF (central differences)')
  end subroutine case_energy

  !> sigma(R F) = R sigma(F) R^T (a rotation of the current frame).
  subroutine case_frame(t, law, tag)
    type(checker_t), intent(inout) :: t
    class(law_t), intent(in) :: law
    character(len=*), intent(in) :: tag
    real(dp) :: f(3, 3), g(3, 3), r(3, 3), s1(6), s2(6), w, hist(law%nhist), hnew(law%nhist)
    integer :: i
    f = 0.0_dp
    f(1:2, 1:2) = reshape([1.05_dp, -0.01_dp, 0.03_dp, 0.97_dp], [2, 2])
    f(3, 3) = 1.0_dp
    r = rotation(0.7_dp)
    hist = 0.0_dp
    g = f
    do i = 1, 3
      g(i, i) = g(i, i) - 1.0_dp
    end do
    call law%stress(g, hist, hnew, s1, w)
    g = matmul(r, f)
    do i = 1, 3
      g(i, i) = g(i, i) - 1.0_dp
    end do
    call law%stress(g, hist, hnew, s2, w)
    call t%close_abs(maxval(abs(tensor_of(s2) - matmul(matmul(r, tensor_of(s1)), &
        transpose(r)))), 0.0_dp, 1.0e-11_dp*maxval(abs(s1)), tag//': sigma(R F) = R sigma R^T')
  end subroutine case_frame

  !> neo-Hookean at a small strain against linear elasticity with mu = 2 C10, K = 2/D1.
  subroutine case_nh_limit(t, nh, lin)
    type(checker_t), intent(inout) :: t
    class(law_t), intent(in) :: nh, lin
    class(law_t), allocatable :: ref
    real(dp) :: g(3, 3), s1(6), s2(6), w, h(0), h2(0), mu, k, e, nu
    mu = 50.0_dp
    k = 100.0_dp
    e = 9.0_dp*k*mu/(3.0_dp*k + mu)
    nu = (3.0_dp*k - 2.0_dp*mu)/(2.0_dp*(3.0_dp*k + mu))
    call material_make_law('LINEAR ELASTIC', [e, nu], lin%kin, ref)
    g = 0.0_dp
    g(1:2, 1:2) = 1.0e-7_dp*reshape([3.0_dp, -1.0_dp, 4.0_dp, -2.0_dp], [2, 2])
    call nh%stress(g, h, h2, s1, w)
    call ref%stress(g, h, h2, s2, w)
    call t%close_abs(maxval(abs(s1 - s2)), 0.0_dp, 1.0e-5_dp*maxval(abs(s2)), &
        'neo-Hookean small-strain limit: mu = 2 C10, K = 2/D1')
  end subroutine case_nh_limit

  !> Uniaxial strain eps_xx = -eps (compression) in steps; sigma_xx against the closed form.
  subroutine case_uniaxial(t, law, tag, tol)
    type(checker_t), intent(inout) :: t
    class(law_t), intent(in) :: law
    character(len=*), intent(in) :: tag
    real(dp), intent(in) :: tol
    real(dp), parameter :: e = 1000.0_dp, nu = 0.3_dp, hh = 100.0_dp
    real(dp) :: hist(law%nhist), hnew(law%nhist), g(3, 3), sig(6), w, eps, want, err
    real(dp) :: mu, lam, m, kb, gep, mp, shel, ehel, epbar
    integer :: n, k
    mu = e/(2.0_dp*(1.0_dp + nu))
    lam = e*nu/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
    m = lam + 2.0_dp*mu
    kb = lam + 2.0_dp*mu/3.0_dp
    gep = mu*hh/(3.0_dp*mu + hh)
    mp = kb + 4.0_dp/3.0_dp*gep
    shel = 5.0_dp*(1.0_dp - nu)/(1.0_dp - 2.0_dp*nu)
    ehel = shel/m
    hist = 0.0_dp
    n = 400
    err = 0.0_dp
    do k = 1, n
      eps = 0.03226_dp*real(k, dp)/real(n, dp)
      g = 0.0_dp
      if (law%kin%nlgeom) then
        ! the stretch whose logarithmic strain is -eps
        g(1, 1) = exp(-eps) - 1.0_dp
      else
        g(1, 1) = -eps
      end if
      call law%stress(g, hist, hnew, sig, w)
      hist = hnew
      want = merge(m*eps, shel + mp*(eps - ehel), eps <= ehel)
      ! Cauchy stress of the finite law is Kirchhoff / J (J = exp(-eps))
      if (law%kin%nlgeom) want = want/exp(-eps)
      err = max(err, abs(-sig(1) - want)/want)
    end do
    call t%close_abs(err, 0.0_dp, tol, tag//': sigma_xx along the uniaxial-strain path')
    if (.not. law%kin%nlgeom) then
      call t%close(-sig(1), 31.266_dp, 3.0e-4_dp, tag//': plateau 31.266 at eps = 0.03226')
      epbar = hist(7)
      call t%close(hist(8), 5.0_dp*epbar + 50.0_dp*epbar**2, 1.0e-10_dp, &
          tag//': plastic work = int sigma_y d epbar')
    end if
  end subroutine case_uniaxial

  pure function rotation(th) result(r)
    real(dp), intent(in) :: th
    real(dp) :: r(3, 3)
    r = 0.0_dp
    r(1, 1) = cos(th)
    r(2, 1) = sin(th)
    r(1, 2) = -sin(th)
    r(2, 2) = cos(th)
    r(3, 3) = 1.0_dp
  end function rotation
end program test_laws
