!> The toy element of doc/architecture.md "Adding an element type": the 3-node linear triangle
!! (constant strain), defined here in tests/ only. Step 1 of the guide: one file with the
!! shape functions, the quadrature rule and `<type>_kind()`.
!!
!! Parent domain: the triangle (0, 0), (1, 0), (0, 1); N1 = 1 - xi - eta, N2 = xi, N3 = eta.
module toy_t3
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: element_kind_t, KERNEL_SOLID2D
  implicit none
  private
  public :: t3_kind

contains

  !> The description the dispatcher keeps (ictus_elements_types: element_kind_t).
  function t3_kind() result(k)
    type(element_kind_t) :: k
    k%name = 'T3TOY'
    k%xdmf = 'Triangle'
    k%ndm = 2
    k%nen = 3
    k%ncorner = 3
    k%ngauss = 1
    k%order = 1
    k%nface = 3
    k%nfn = 2
    allocate(k%face(2, 3))
    k%face = reshape([1, 2, 2, 3, 3, 1], [2, 3])
    k%kernel = KERNEL_SOLID2D
    k%shape => t3_shape
    k%rule => t3_rule
  end function t3_kind

  pure subroutine t3_shape(xi, n, dn)
    real(dp), intent(in) :: xi(:)
    real(dp), intent(out) :: n(:), dn(:,:)
    n(1:3) = [1.0_dp - xi(1) - xi(2), xi(1), xi(2)]
    dn(1, 1:3) = [-1.0_dp, 1.0_dp, 0.0_dp]
    dn(2, 1:3) = [-1.0_dp, 0.0_dp, 1.0_dp]
  end subroutine t3_shape

  !> The centroid rule (exact for linear integrands; the mass of a constant-strain triangle
  !! needs the 3-point rule at the edge midpoints, exact for quadratics: n >= 2).
  pure subroutine t3_rule(n, xq, wq)
    integer, intent(in) :: n
    real(dp), allocatable, intent(out) :: xq(:,:), wq(:)
    if (n <= 1) then
      xq = reshape([1.0_dp/3.0_dp, 1.0_dp/3.0_dp], [2, 1])
      wq = [0.5_dp]
    else
      xq = reshape([0.5_dp, 0.0_dp, 0.5_dp, 0.5_dp, 0.0_dp, 0.5_dp], [2, 3])
      wq = [1.0_dp, 1.0_dp, 1.0_dp]/6.0_dp
    end if
  end subroutine t3_rule
end module toy_t3
