!> Bezier extraction of B-spline bases, Bernstein polynomials and Bezier curves.
!!
!! Borden, Scott, Evans & Hughes, IJNME 87 (2011) 15-47, Algorithm 1: on the e-th non-empty
!! knot span the p+1 non-zero B-splines satisfy N^e(u) = C^e B(t), with B the Bernstein
!! polynomials of degree p in the local variable t in [0, 1] mapped linearly onto the span.
!!
!! The one place where Bernstein polynomials and Bezier curves are evaluated, all by de
!! Casteljau's recursion B_{i,q} = (1-t) B_{i,q-1} + t B_{i-1,q-1}:
!! * `bernstein`: values and first derivatives (the element shape functions, the viewing
!!   samples);
!! * `bernstein_values`: values alone, and `bernstein_d2`: values, first and second
!!   derivatives from the values of degrees p, p-1 and p-2 (the contact segments);
!! * `de_casteljau`: a point of a Bezier curve given by its Bezier points, with its first and
!!   second derivatives (the contact segment curves).
!! For finite t, `bernstein` and `bernstein_d2` give the same numbers but for the sign of a
!! zero: `bernstein` leaves out the terms of the recursion that are known to be zero, where
!! `bernstein_d2` adds them. They are kept as two routines so that each kernel keeps its bits.
module ictus_geometry_bezier
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: bezier_extraction_1d, bernstein, count_spans, bernstein_values, bernstein_d2, &
      de_casteljau, BEZIER_MAX_DEGREE

  !> Highest degree `bernstein_d2` and `de_casteljau` accept: the size of their fixed local
  !! arrays, so that they allocate nothing (they run in the contact step).
  integer, parameter :: BEZIER_MAX_DEGREE = 15

contains

  !> Number of non-empty knot spans of a knot vector with n functions of degree p.
  !! @param n number of basis functions; @param p degree; @param knots (n+p+1)
  pure integer function count_spans(n, p, knots) result(nel)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: knots(:)
    integer :: i
    nel = 0
    do i = p + 1, n
      if (knots(i+1) > knots(i)) nel = nel + 1
    end do
  end function count_spans

  !> Extraction operators of all non-empty knot spans (Borden et al. 2011, Algorithm 1).
  !! @param n number of basis functions; @param p degree; @param knots open knot vector
  !! (n+p+1); @param nel number of non-empty spans (elements);
  !! @param c extraction operators (p+1, p+1, nel): N_{a-p+i-1}(u) = sum_j c(i, j, e) B_j(t)
  subroutine bezier_extraction_1d(n, p, knots, nel, c)
    integer, intent(in) :: n, p
    real(dp), intent(in) :: knots(:)
    integer, intent(out) :: nel
    real(dp), allocatable, intent(out) :: c(:,:,:)
    real(dp), allocatable :: cw(:,:,:)
    real(dp) :: alphas(p), numer, alpha
    integer :: m, a, b, nb, i, j, k, mult, r, s, save_
    m = n + p + 1
    nel = count_spans(n, p, knots)
    allocate(cw(p+1, p+1, nel+1))
    cw = 0.0_dp
    do i = 1, p + 1
      cw(i, i, 1) = 1.0_dp
    end do
    a = p + 1
    b = a + 1
    nb = 1
    do while (b < m)
      do i = 1, p + 1
        cw(i, i, nb+1) = 1.0_dp
      end do
      i = b
      do while (b < m)
        if (knots(b+1) /= knots(b)) exit
        b = b + 1
      end do
      mult = b - i + 1
      if (mult < p) then
        numer = knots(b) - knots(a)
        do j = p, mult + 1, -1
          alphas(j-mult) = numer/(knots(a+j) - knots(a))
        end do
        r = p - mult
        do j = 1, r
          save_ = r - j + 1
          s = mult + j
          do k = p + 1, s + 1, -1
            alpha = alphas(k-s)
            cw(:, k, nb) = alpha*cw(:, k, nb) + (1.0_dp - alpha)*cw(:, k-1, nb)
          end do
          if (b < m) then
            cw(save_:j+save_, save_, nb+1) = cw(p-j+1:p+1, p+1, nb)
          end if
        end do
      end if
      nb = nb + 1
      if (b < m) then
        a = b
        b = b + 1
      end if
    end do
    allocate(c(p+1, p+1, nel))
    c = cw(:, :, 1:nel)
  end subroutine bezier_extraction_1d

  !> Bernstein polynomials of degree p on t in [0, 1] and their derivatives d/dt.
  !! @param p degree; @param t local coordinate; @param b values (p+1),
  !! b(i) = binom(p, i-1) t^(i-1) (1-t)^(p-i+1); @param db derivatives (p+1)
  pure subroutine bernstein(p, t, b, db)
    integer, intent(in) :: p
    real(dp), intent(in) :: t
    real(dp), intent(out) :: b(p+1), db(p+1)
    real(dp) :: bl(p+1), s
    integer :: q, i
    ! de Casteljau-type recursion B_{i,q} = (1-t) B_{i,q-1} + t B_{i-1,q-1}
    bl = 0.0_dp
    bl(1) = 1.0_dp
    s = 1.0_dp - t
    do q = 1, p - 1
      do i = q + 1, 2, -1
        bl(i) = s*bl(i) + t*bl(i-1)
      end do
      bl(1) = s*bl(1)
    end do
    ! bl(1:p) now holds degree p-1 (for p >= 1)
    if (p == 0) then
      b(1) = 1.0_dp
      db(1) = 0.0_dp
      return
    end if
    b(1) = s*bl(1)
    db(1) = -real(p, dp)*bl(1)
    do i = 2, p
      b(i) = s*bl(i) + t*bl(i-1)
      db(i) = real(p, dp)*(bl(i-1) - bl(i))
    end do
    b(p+1) = t*bl(p)
    db(p+1) = real(p, dp)*bl(p)
  end subroutine bernstein

  !> Bernstein polynomials of degree q at t, (q+1) values, by de Casteljau's recursion.
  !! @param q degree (>= 0); @param t parameter; @param b values (q+1)
  pure subroutine bernstein_values(q, t, b)
    integer, intent(in) :: q
    real(dp), intent(in) :: t
    real(dp), intent(out) :: b(q+1)
    integer :: k, i
    b = 0.0_dp
    b(1) = 1.0_dp
    do k = 1, q
      do i = k + 1, 2, -1
        b(i) = (1.0_dp - t)*b(i) + t*b(i-1)
      end do
      b(1) = (1.0_dp - t)*b(1)
    end do
  end subroutine bernstein_values

  !> Bernstein polynomials of degree p on [0, 1] with first and second derivatives:
  !! B_i' = p (B_{i-1,p-1} - B_{i,p-1}),
  !! B_i'' = p (p-1) (B_{i-2,p-2} - 2 B_{i-1,p-2} + B_{i,p-2}).
  !! @param p degree, 0 <= p <= BEZIER_MAX_DEGREE; @param t parameter;
  !! @param b, db, ddb values and derivatives d/dt (p+1)
  pure subroutine bernstein_d2(p, t, b, db, ddb)
    integer, intent(in) :: p
    real(dp), intent(in) :: t
    real(dp), intent(out) :: b(p+1), db(p+1), ddb(p+1)
    real(dp) :: b1(0:BEZIER_MAX_DEGREE+1), b2(0:BEZIER_MAX_DEGREE+1)
    integer :: i
    ! b1: degree p-1 at 1..p (zero padded), b2: degree p-2 at 1..p-1
    call bernstein_values(p, t, b)
    b1 = 0.0_dp
    b2 = 0.0_dp
    if (p >= 1) call bernstein_values(p - 1, t, b1(1:p))
    if (p >= 2) call bernstein_values(p - 2, t, b2(1:p-1))
    do i = 1, p + 1
      db(i) = real(p, dp)*(b1(i-1) - b1(i))
      ddb(i) = 0.0_dp
      if (p >= 2) then
        ddb(i) = real(p*(p - 1), dp)*(bm(i - 2) - 2.0_dp*bm(i - 1) + bm(i))
      end if
    end do
  contains
    pure real(dp) function bm(k)
      integer, intent(in) :: k
      bm = 0.0_dp
      if (k >= 1 .and. k <= p - 1) bm = b2(k)
    end function bm
  end subroutine bernstein_d2

  !> Point h0 of the Bezier curve of degree p with Bezier points h(:, 1:p+1) at t and, if
  !! asked, its first and second derivatives h1, h2 d/dt, by de Casteljau's recursion, each
  !! component on its own: after p - 2 levels the three remaining points give
  !! h2 = p (p-1) (q_1 - 2 q_2 + q_3), after p - 1 levels the two remaining ones
  !! h1 = p (q_2 - q_1), after p levels the point. Any number of components (rows of h), e.g.
  !! homogeneous points (w x, w y, w) of a rational curve.
  !! @param p degree, 0 <= p <= BEZIER_MAX_DEGREE; @param h Bezier points (:, p+1 or more);
  !! @param t parameter; @param h0 point (size(h, 1)); @param h1, h2 derivatives, optional
  pure subroutine de_casteljau(p, h, t, h0, h1, h2)
    integer, intent(in) :: p
    real(dp), intent(in) :: h(:,:), t
    real(dp), intent(out) :: h0(:)
    real(dp), intent(out), optional :: h1(:), h2(:)
    real(dp) :: q(BEZIER_MAX_DEGREE+1), u
    integer :: d, k, i
    u = 1.0_dp - t
    do d = 1, size(h, 1)
      do i = 1, p + 1
        q(i) = h(d, i)
      end do
      do k = 1, p
        if (k == p - 1 .and. present(h2)) h2(d) = real(p*(p - 1), dp)*(q(1) - 2.0_dp*q(2) + &
            q(3))
        if (k == p .and. present(h1)) h1(d) = real(p, dp)*(q(2) - q(1))
        do i = 1, p + 1 - k
          q(i) = u*q(i) + t*q(i+1)
        end do
      end do
      h0(d) = q(1)
    end do
    if (p < 1 .and. present(h1)) h1 = 0.0_dp
    if (p < 2 .and. present(h2)) h2 = 0.0_dp
  end subroutine de_casteljau
end module ictus_geometry_bezier
