!> The trivariate NURBS patches of a 3D model (doc/iga.md §11): the deck's *PATCH records
!! become `volume_t`s (ictus_geometry_volume) in model%volumes, refined by *ELEVATE and
!! *REFINE in deck order, each refinement checked against the largest degree and the memory
!! first. The 3D counterpart of build_patches in ictus_app_build_model, which calls it.
module ictus_app_build_volumes
  use ictus_core_kinds, only: dp, i8
  use ictus_core_memory, only: available_memory
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: str, str_list, upper
  use ictus_geometry_volume, only: volume_init, volume_refine, volume_elevate
  use ictus_solver_model, only: model_t, patch_name
  use ictus_io_deck_types, only: deck_t, OP_ELEVATE, OP_REFINE
  implicit none
  private
  public :: build_volumes

contains

  !> model%volumes from deck%patches (3D), then *ELEVATE / *REFINE in deck order; degrees
  !! above max_degree and refinements that would not fit in memory are reported at their card.
  subroutine build_volumes(deck, model, max_degree)
    type(deck_t), intent(in) :: deck
    type(model_t), intent(inout) :: model
    integer, intent(in) :: max_degree
    integer :: ip, k, j
    integer(i8) :: n_new(3)
    model%npatch = deck%n_patches
    allocate(model%volumes(model%npatch), model%patches(0), model%patch_offset(model%npatch))
    do ip = 1, model%npatch
      associate (pin => deck%patches(ip))
        call volume_init(model%volumes(ip), pin%name, pin%degree, pin%size, pin%knots1, &
            pin%knots2, pin%knots3, pin%cp)
      end associate
    end do
    do k = 1, deck%n_patch_ops
      j = 0
      do ip = 1, model%npatch
        if (upper(patch_name(model, ip)) == upper(trim(deck%patch_ops(k)%patch))) j = ip
      end do
      if (j == 0) cycle
      associate (op => deck%patch_ops(k), v => model%volumes(j))
        select case (op%kind)
        case (OP_ELEVATE)
          if (any(op%values < v%p)) then
            call input_error(op%where, '*ELEVATE: DEGREE must not be below the current '// &
                'degree '//str_list(v%p))
            cycle
          end if
          if (any(op%values > max_degree)) then
            call input_error(op%where, '*ELEVATE: DEGREE='//str_list(op%values)// &
                ' is above the largest degree ictus takes, '//str(max_degree))
            cycle
          end if
          ! each of the at most n - p spans gains q - p control points per direction
          n_new = int(v%n, i8) + int(op%values - v%p, i8)*int(v%n - v%p, i8)
          if (.not. volume_fits(op%where, '*ELEVATE', trim(v%name), n_new, op%values, &
              other_volumes_bytes(model, j))) cycle
          call volume_elevate(v, op%values - v%p)
        case (OP_REFINE)
          n_new = int(v%n, i8) + int(op%values - 1, i8)*int(v%n - v%p, i8)
          if (.not. volume_fits(op%where, '*REFINE', trim(v%name), n_new, v%p, &
              other_volumes_bytes(model, j))) cycle
          call volume_refine(v, op%values)
        end select
      end associate
    end do
  end subroutine build_volumes

  !> Whether a volume of at most n(1) n(2) n(3) control points of degree p still fits in the
  !! memory left on this node (volume_bytes, plus `other` bytes of the other patches);
  !! reports it at `where` otherwise.
  logical function volume_fits(where, card, name, n, p, other) result(ok)
    character(len=*), intent(in) :: where, card, name
    integer(i8), intent(in) :: n(3)
    integer, intent(in) :: p(3)
    real(dp), intent(in) :: other
    integer(i8) :: avail
    real(dp) :: need
    ok = .true.
    avail = available_memory()
    need = volume_bytes(n, p) + other
    if (avail >= 0 .and. need > real(avail, dp)) then
      call input_error(where, card//': patch '//name//' would have up to '// &
          str(product(n))//' control points; the set-up of the model would need about '// &
          str(need/1024.0_dp**3)//' GB, more than the '// &
          str(real(avail, dp)/1024.0_dp**3)//' GB available (/proc/meminfo, the control '// &
          'group, ulimit -v, ICTUS_MEMORY_LIMIT_MB; a smaller refinement, or more memory)')
      ok = .false.
    end if
  end function volume_fits

  !> Memory of the set-up for a volume of n(1) n(2) n(3) control points of degree p, at most
  !! one element per control point: the element loop's stored geometry, 3 nen + 1 doubles per
  !! Gauss point ((p + 1)^3 points of nen = (p + 1)^3 control points), a consistent mass row
  !! of (2 p + 1)^3 entries (12 bytes each) and about 800 bytes for everything else per
  !! control point.
  pure real(dp) function volume_bytes(n, p)
    integer(i8), intent(in) :: n(3)
    integer, intent(in) :: p(3)
    real(dp) :: ncp, nen
    ncp = real(n(1), dp)*real(n(2), dp)*real(n(3), dp)
    nen = real(product(p + 1), dp)
    volume_bytes = ncp*(8.0_dp*(3.0_dp*nen + 1.0_dp)*nen + &
        12.0_dp*real(product(2*p + 1), dp) + 800.0_dp)
  end function volume_bytes

  !> volume_bytes of all volumes but volume j, at their present sizes.
  real(dp) function other_volumes_bytes(model, j) result(b)
    type(model_t), intent(in) :: model
    integer, intent(in) :: j
    integer :: ip
    b = 0.0_dp
    do ip = 1, model%npatch
      if (ip /= j) b = b + volume_bytes(int(model%volumes(ip)%n, i8), model%volumes(ip)%p)
    end do
  end function other_volumes_bytes
end module ictus_app_build_volumes
