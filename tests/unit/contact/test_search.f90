!> Global search: the bucket grid returns exactly the boxes a brute-force search finds, on
!! random configurations (uniform small boxes, mixed sizes, widely spread boxes).
program test_search
  use ictus_core_kinds, only: dp
  use ictus_test_check, only: checker_t
  use ictus_contact_search, only: search_grid_t, grid_init, grid_build, grid_query, &
      box_contains
  implicit none
  type(checker_t) :: t
  call t%start("contact/search")
  call random_case(t, 200, 0.05_dp, 0.0_dp, 1.0_dp, 'uniform')
  call random_case(t, 300, 0.02_dp, 0.5_dp, 1.0_dp, 'mixed sizes')
  call random_case(t, 100, 0.01_dp, 0.0_dp, 1000.0_dp, 'spread out')
  call random_case(t, 1, 0.1_dp, 0.0_dp, 1.0_dp, 'one box')
  call t%finish()

contains

  !> nbox random boxes of size up to `size` in [0, span]^2 (a fraction `big` of them up to
  !! 20 times larger); 2000 random query points.
  subroutine random_case(t, nbox, size, big, span, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: nbox
    real(dp), intent(in) :: size, big, span
    character(len=*), intent(in) :: label
    type(search_grid_t) :: g
    real(dp) :: r(4), xp(2)
    integer :: k, q, ncand, nbrute, nwrong
    integer, allocatable :: cand(:)
    logical :: same
    integer, allocatable :: seed(:)
    call random_seed(size=k)
    allocate(seed(k))
    seed = 12345
    call random_seed(put=seed)
    call grid_init(g, nbox)
    allocate(cand(nbox))
    do k = 1, nbox
      call random_number(r)
      g%box(1:2, k) = r(1:2)*span
      g%box(3:4, k) = g%box(1:2, k) + r(3:4)*size*span
      call random_number(r(1))
      if (r(1) < big) g%box(3:4, k) = g%box(1:2, k) + 20.0_dp*r(3:4)*size*span
    end do
    call grid_build(g)
    call t%true(g%nx*g%ny <= g%ncell_cap, label//': cells within capacity')
    nwrong = 0
    do q = 1, 2000
      call random_number(xp)
      xp = (1.1_dp*xp - 0.05_dp)*span
      ! every other point inside a random box, so that hits are frequent
      if (mod(q, 2) == 0) then
        k = 1 + mod(q, nbox)
        call random_number(r(1:2))
        xp = g%box(1:2, k) + r(1:2)*(g%box(3:4, k) - g%box(1:2, k))
      end if
      call grid_query(g, xp, cand, ncand)
      nbrute = 0
      same = .true.
      do k = 1, nbox
        if (box_contains(g%box(:, k), xp)) then
          nbrute = nbrute + 1
          if (nbrute > ncand) then
            same = .false.
          else if (cand(nbrute) /= k) then
            same = .false.
          end if
        end if
      end do
      if (nbrute /= ncand .or. .not. same) nwrong = nwrong + 1
    end do
    call t%equal_int(nwrong, 0, label//': grid = brute force')
  end subroutine random_case
end program test_search
