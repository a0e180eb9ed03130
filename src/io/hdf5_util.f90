!> Thin, checked wrappers around the HDF5 Fortran API for the results and checkpoint files.
!!
!! Files are opened through MPI-IO (parallel HDF5) with collective transfers. The data of a
!! write is taken from rank 0 (the others select nothing), so every call is collective and
!! the file layout does not depend on the number of ranks. Every HDF5 status is checked; a
!! failure is a run-time error naming the object.
module ictus_io_hdf5_util
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5fcreate_f, h5fclose_f, &
      h5fflush_f, h5pcreate_f, h5pclose_f, h5pset_fapl_mpio_f, h5pset_dxpl_mpio_f, &
      h5pset_libver_bounds_f, h5pset_chunk_f, h5gcreate_f, h5gclose_f, h5gopen_f, &
      h5screate_f, h5screate_simple_f, h5sclose_f, h5sselect_none_f, h5sselect_hyperslab_f, &
      h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, h5dset_extent_f, h5dget_space_f, &
      h5sget_simple_extent_dims_f, h5sget_simple_extent_ndims_f, h5sselect_elements_f, &
      h5acreate_f, h5awrite_f, h5aclose_f, h5tcopy_f, &
      h5tset_size_f, h5tclose_f, h5lexists_f, h5fopen_f, h5dread_f, h5aopen_f, h5aread_f, &
      h5adelete_f, h5aexists_f, h5eset_auto_f, h5aget_type_f, h5tget_size_f, h5ldelete_f, &
      h5gn_members_f, h5gget_obj_info_idx_f, &
      H5F_ACC_RDWR_F, H5F_ACC_RDONLY_F, H5F_ACC_TRUNC_F, H5P_FILE_ACCESS_F, H5P_DATASET_XFER_F, &
      H5P_DATASET_CREATE_F, H5F_LIBVER_V18_F, H5F_LIBVER_LATEST_F, H5FD_MPIO_COLLECTIVE_F, &
      H5S_SCALAR_F, H5S_UNLIMITED_F, H5S_SELECT_SET_F, H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER, &
      H5T_NATIVE_CHARACTER, H5F_SCOPE_GLOBAL_F
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: fatal, input_error, terminate
  use ictus_parallel_env, only: env_comm_f, env_info_null_f, env_is_root
  implicit none
  private
  public :: hid_t, h5u_create_file, h5u_close_file, h5u_flush, h5u_group, h5u_close_group, &
      h5u_attr_string, h5u_attr_int, h5u_attr_real, h5u_write, h5u_create_ext, h5u_append, &
      h5u_exists, h5u_write_rows, h5u_open_file, h5u_read, h5u_read_attr_real, &
      h5u_read_attr_int, h5u_read_attr_string, h5u_truncate, h5u_delete, h5u_delete_attr, &
      h5u_extent, h5u_members

  !> Writes a whole dataset (data from rank 0).
  interface h5u_write
    module procedure write_real1, write_real2, write_int1, write_int2
  end interface h5u_write
  !> Reads a whole dataset on every rank.
  interface h5u_read
    module procedure read_real1, read_real2, read_int1
  end interface h5u_read
  !> Writes a dataset of nglobal rows of which every rank holds some (its owned nodes).
  interface h5u_write_rows
    module procedure write_rows1, write_rows2
  end interface h5u_write_rows
  !> Appends records to an extendible dataset created by h5u_create_ext.
  interface h5u_append
    module procedure append_real1, append_real2, append_int1
  end interface h5u_append

  !> The collective transfer property list (one for all files, made on first use).
  integer(hid_t) :: dxpl = -1

contains

  !> Stops the run with a message when an HDF5 call failed.
  subroutine check(err, what)
    integer, intent(in) :: err
    character(len=*), intent(in) :: what
    if (err < 0) call fatal('HDF5', 'failed: '//what)
  end subroutine check

  !> Creates (truncates) a results file for collective parallel access.
  subroutine h5u_create_file(path, file_id)
    character(len=*), intent(in) :: path
    integer(hid_t), intent(out) :: file_id
    integer(hid_t) :: fapl
    integer :: err
    call h5open_f(err)
    call check(err, 'h5open')
    ! every status is checked here; HDF5's own error stack would only repeat it at length
    call h5eset_auto_f(0, err)
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, err)
    call check(err, 'h5pcreate fapl')
    call h5pset_fapl_mpio_f(fapl, env_comm_f(), env_info_null_f(), err)
    call check(err, 'h5pset_fapl_mpio')
    ! the newer object format allows attributes larger than 64 KiB (the processed deck)
    call h5pset_libver_bounds_f(fapl, H5F_LIBVER_V18_F, H5F_LIBVER_LATEST_F, err)
    call check(err, 'h5pset_libver_bounds')
    call h5fcreate_f(path, H5F_ACC_TRUNC_F, file_id, err, access_prp=fapl)
    if (err < 0) then
      call input_error(path, 'cannot create this results file (does its directory exist, '// &
          'and may it be written?)')
      call terminate(1)
    end if
    call h5pclose_f(fapl, err)
    call make_dxpl()
  end subroutine h5u_create_file

  !> The collective transfer property list, made once and shared by all open files.
  subroutine make_dxpl()
    integer :: err
    if (dxpl >= 0) return
    call h5pcreate_f(H5P_DATASET_XFER_F, dxpl, err)
    call check(err, 'h5pcreate dxpl')
    call h5pset_dxpl_mpio_f(dxpl, H5FD_MPIO_COLLECTIVE_F, err)
    call check(err, 'h5pset_dxpl_mpio')
  end subroutine make_dxpl

  !> Opens an existing file for collective parallel access (read-only unless `readwrite`).
  !! `ok` is false when the file cannot be opened (the caller reports it).
  subroutine h5u_open_file(path, readwrite, file_id, ok)
    character(len=*), intent(in) :: path
    logical, intent(in) :: readwrite
    integer(hid_t), intent(out) :: file_id
    logical, intent(out) :: ok
    integer(hid_t) :: fapl
    integer :: err
    logical :: exists
    ok = .false.
    file_id = -1
    inquire(file=path, exist=exists)
    if (.not. exists) return
    call h5open_f(err)
    call h5eset_auto_f(0, err)
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, err)
    call h5pset_fapl_mpio_f(fapl, env_comm_f(), env_info_null_f(), err)
    call h5pset_libver_bounds_f(fapl, H5F_LIBVER_V18_F, H5F_LIBVER_LATEST_F, err)
    if (readwrite) then
      call h5fopen_f(path, H5F_ACC_RDWR_F, file_id, err, access_prp=fapl)
    else
      call h5fopen_f(path, H5F_ACC_RDONLY_F, file_id, err, access_prp=fapl)
    end if
    ok = err >= 0
    call h5pclose_f(fapl, err)
    if (.not. ok) then
      file_id = -1
      return
    end if
    ok = .true.
    call make_dxpl()
  end subroutine h5u_open_file

  !> Current shape of a dataset (up to rank 2; dims(2) = 0 for rank 1), Fortran order.
  subroutine h5u_extent(loc, name, dims)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(out) :: dims(2)
    integer(hid_t) :: did, fs
    integer(hsize_t) :: d(2), md(2)
    integer :: err, rank
    call h5dopen_f(loc, name, did, err)
    call check(err, 'opening '//name)
    call h5dget_space_f(did, fs, err)
    call h5sget_simple_extent_ndims_f(fs, rank, err)
    d = 0
    call h5sget_simple_extent_dims_f(fs, d(1:rank), md(1:rank), err)
    dims = int(d)
    if (rank == 1) dims(2) = 0
    call h5sclose_f(fs, err)
    call h5dclose_f(did, err)
  end subroutine h5u_extent

  subroutine read_real1(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(out) :: x(:)
    integer(hid_t) :: did
    integer :: err
    call h5dopen_f(loc, name, did, err)
    call check(err, 'opening '//name)
    call h5dread_f(did, H5T_NATIVE_DOUBLE, x, shape(x, kind=hsize_t), err, xfer_prp=dxpl)
    call check(err, 'reading '//name)
    call h5dclose_f(did, err)
  end subroutine read_real1

  subroutine read_real2(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(out) :: x(:,:)
    integer(hid_t) :: did
    integer :: err
    call h5dopen_f(loc, name, did, err)
    call check(err, 'opening '//name)
    call h5dread_f(did, H5T_NATIVE_DOUBLE, x, shape(x, kind=hsize_t), err, xfer_prp=dxpl)
    call check(err, 'reading '//name)
    call h5dclose_f(did, err)
  end subroutine read_real2

  subroutine read_int1(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(out) :: x(:)
    integer(hid_t) :: did
    integer :: err
    call h5dopen_f(loc, name, did, err)
    call check(err, 'opening '//name)
    call h5dread_f(did, H5T_NATIVE_INTEGER, x, shape(x, kind=hsize_t), err, xfer_prp=dxpl)
    call check(err, 'reading '//name)
    call h5dclose_f(did, err)
  end subroutine read_int1

  real(dp) function h5u_read_attr_real(loc, name) result(v)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(hid_t) :: aid
    integer(hsize_t) :: dims(1)
    integer :: err
    dims = 1
    call h5aopen_f(loc, name, aid, err)
    call check(err, 'opening attribute '//name)
    call h5aread_f(aid, H5T_NATIVE_DOUBLE, v, dims, err)
    call h5aclose_f(aid, err)
  end function h5u_read_attr_real

  integer function h5u_read_attr_int(loc, name) result(v)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(hid_t) :: aid
    integer(hsize_t) :: dims(1)
    integer :: err
    dims = 1
    call h5aopen_f(loc, name, aid, err)
    call check(err, 'opening attribute '//name)
    call h5aread_f(aid, H5T_NATIVE_INTEGER, v, dims, err)
    call h5aclose_f(aid, err)
  end function h5u_read_attr_int

  !> A string attribute ('' when it does not exist).
  function h5u_read_attr_string(loc, name) result(v)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: v
    integer(hid_t) :: aid, tid
    integer(size_t) :: n
    integer(hsize_t) :: dims(1)
    integer :: err
    logical :: exists
    v = ''
    call h5aexists_f(loc, name, exists, err)
    if (.not. exists) return
    dims = 1
    call h5aopen_f(loc, name, aid, err)
    call h5aget_type_f(aid, tid, err)
    call h5tget_size_f(tid, n, err)
    deallocate(v)
    allocate(character(len=n) :: v)
    call h5aread_f(aid, tid, v, dims, err)
    call check(err, 'reading attribute '//name)
    call h5tclose_f(tid, err)
    call h5aclose_f(aid, err)
  end function h5u_read_attr_string

  !> Cuts an extendible record dataset (rank 1 or 2, records last in Fortran order) to nrec.
  subroutine h5u_truncate(loc, name, nrec)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: nrec
    integer(hid_t) :: did
    integer :: dims(2), err
    call h5u_extent(loc, name, dims)
    call h5dopen_f(loc, name, did, err)
    if (dims(2) == 0) then
      call h5dset_extent_f(did, [int(nrec, hsize_t)], err)
    else
      call h5dset_extent_f(did, [int(dims(1), hsize_t), int(nrec, hsize_t)], err)
    end if
    call check(err, 'truncating '//name)
    call h5dclose_f(did, err)
  end subroutine h5u_truncate

  !> Removes the link `name` below `loc` if it exists.
  subroutine h5u_delete(loc, name)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer :: err
    if (.not. h5u_exists(loc, name)) return
    call h5ldelete_f(loc, name, err)
    call check(err, 'deleting '//name)
  end subroutine h5u_delete

  !> The names of the members of the group `name` below `loc` (none if it does not exist);
  !! names longer than `len(names)` are cut.
  subroutine h5u_members(loc, name, names)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    character(len=*), allocatable, intent(out) :: names(:)
    integer :: err, n, k, otype
    if (.not. h5u_exists(loc, name)) then
      allocate(names(0))
      return
    end if
    call h5gn_members_f(loc, name, n, err)
    call check(err, 'listing '//name)
    allocate(names(n))
    do k = 1, n
      call h5gget_obj_info_idx_f(loc, name, k - 1, names(k), otype, err)
      call check(err, 'listing '//name)
    end do
  end subroutine h5u_members

  !> Removes the attribute `name` of `loc` if it exists.
  subroutine h5u_delete_attr(loc, name)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer :: err
    logical :: exists
    call h5aexists_f(loc, name, exists, err)
    if (.not. exists) return
    call h5adelete_f(loc, name, err)
    call check(err, 'deleting attribute '//name)
  end subroutine h5u_delete_attr

  subroutine h5u_close_file(file_id)
    integer(hid_t), intent(inout) :: file_id
    integer :: err
    if (file_id < 0) return
    call h5fclose_f(file_id, err)
    call check(err, 'closing the results file')
    file_id = -1
  end subroutine h5u_close_file

  !> Flushes everything written so far to disk, so the file is readable if the run stops.
  subroutine h5u_flush(file_id)
    integer(hid_t), intent(in) :: file_id
    integer :: err
    call h5fflush_f(file_id, H5F_SCOPE_GLOBAL_F, err)
    call check(err, 'h5fflush')
  end subroutine h5u_flush

  !> True when a link `name` exists below `loc`.
  logical function h5u_exists(loc, name)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer :: err
    call h5lexists_f(loc, name, h5u_exists, err)
    if (err < 0) h5u_exists = .false.
  end function h5u_exists

  !> Opens group `name` below `loc`, creating it if needed (one level).
  subroutine h5u_group(loc, name, gid)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(hid_t), intent(out) :: gid
    integer :: err
    if (h5u_exists(loc, name)) then
      call h5gopen_f(loc, name, gid, err)
    else
      call h5gcreate_f(loc, name, gid, err)
    end if
    call check(err, 'group '//name)
  end subroutine h5u_group

  subroutine h5u_close_group(gid)
    integer(hid_t), intent(in) :: gid
    integer :: err
    call h5gclose_f(gid, err)
    call check(err, 'h5gclose')
  end subroutine h5u_close_group

  subroutine h5u_attr_string(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name, value
    integer(hid_t) :: tid, sid, aid
    integer(hsize_t) :: dims(1)
    integer :: err
    dims = 1
    call h5tcopy_f(H5T_NATIVE_CHARACTER, tid, err)
    call h5tset_size_f(tid, int(max(len(value), 1), hsize_t), err)
    call h5screate_f(H5S_SCALAR_F, sid, err)
    call h5acreate_f(loc, name, tid, sid, aid, err)
    call check(err, 'attribute '//name)
    if (len(value) > 0) then
      call h5awrite_f(aid, tid, value, dims, err)
    else
      call h5awrite_f(aid, tid, ' ', dims, err)
    end if
    call check(err, 'writing attribute '//name)
    call h5aclose_f(aid, err)
    call h5sclose_f(sid, err)
    call h5tclose_f(tid, err)
  end subroutine h5u_attr_string

  subroutine h5u_attr_int(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: value
    integer(hid_t) :: sid, aid
    integer(hsize_t) :: dims(1)
    integer :: err
    dims = 1
    call h5screate_f(H5S_SCALAR_F, sid, err)
    call h5acreate_f(loc, name, H5T_NATIVE_INTEGER, sid, aid, err)
    call check(err, 'attribute '//name)
    call h5awrite_f(aid, H5T_NATIVE_INTEGER, value, dims, err)
    call check(err, 'writing attribute '//name)
    call h5aclose_f(aid, err)
    call h5sclose_f(sid, err)
  end subroutine h5u_attr_int

  subroutine h5u_attr_real(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: value
    integer(hid_t) :: sid, aid
    integer(hsize_t) :: dims(1)
    integer :: err
    dims = 1
    call h5screate_f(H5S_SCALAR_F, sid, err)
    call h5acreate_f(loc, name, H5T_NATIVE_DOUBLE, sid, aid, err)
    call check(err, 'attribute '//name)
    call h5awrite_f(aid, H5T_NATIVE_DOUBLE, value, dims, err)
    call check(err, 'writing attribute '//name)
    call h5aclose_f(aid, err)
    call h5sclose_f(sid, err)
  end subroutine h5u_attr_real

  !> Creates a fixed-size dataset of rank size(dims) and returns it with a file space in which
  !! rank 0 selects everything and the other ranks nothing.
  subroutine open_fixed(loc, name, dtype, dims, did, fspace)
    integer(hid_t), intent(in) :: loc, dtype
    character(len=*), intent(in) :: name
    integer(hsize_t), intent(in) :: dims(:)
    integer(hid_t), intent(out) :: did, fspace
    integer :: err
    call h5screate_simple_f(size(dims), dims, fspace, err)
    call check(err, 'dataspace '//name)
    call h5dcreate_f(loc, name, dtype, fspace, did, err)
    call check(err, 'dataset '//name)
    if (.not. env_is_root()) call h5sselect_none_f(fspace, err)
  end subroutine open_fixed

  !> Memory space matching `fspace`'s selection on this rank.
  subroutine mem_space(dims, mspace)
    integer(hsize_t), intent(in) :: dims(:)
    integer(hid_t), intent(out) :: mspace
    integer :: err
    call h5screate_simple_f(size(dims), dims, mspace, err)
    if (.not. env_is_root()) call h5sselect_none_f(mspace, err)
  end subroutine mem_space

  subroutine close_ds(did, fspace, mspace, name, err)
    integer(hid_t), intent(in) :: did, fspace, mspace
    character(len=*), intent(in) :: name
    integer, intent(in) :: err
    integer :: e2
    call check(err, 'writing '//name)
    call h5sclose_f(mspace, e2)
    call h5sclose_f(fspace, e2)
    call h5dclose_f(did, e2)
  end subroutine close_ds

  subroutine write_real1(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:)
    integer(hid_t) :: did, fs, ms
    integer(hsize_t) :: dims(1)
    integer :: err
    dims = shape(x, kind=hsize_t)
    call open_fixed(loc, name, H5T_NATIVE_DOUBLE, dims, did, fs)
    call mem_space(dims, ms)
    call h5dwrite_f(did, H5T_NATIVE_DOUBLE, x, dims, err, mem_space_id=ms, &
        file_space_id=fs, xfer_prp=dxpl)
    call close_ds(did, fs, ms, name, err)
  end subroutine write_real1

  subroutine write_real2(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:,:)
    integer(hid_t) :: did, fs, ms
    integer(hsize_t) :: dims(2)
    integer :: err
    dims = shape(x, kind=hsize_t)
    call open_fixed(loc, name, H5T_NATIVE_DOUBLE, dims, did, fs)
    call mem_space(dims, ms)
    call h5dwrite_f(did, H5T_NATIVE_DOUBLE, x, dims, err, mem_space_id=ms, &
        file_space_id=fs, xfer_prp=dxpl)
    call close_ds(did, fs, ms, name, err)
  end subroutine write_real2

  subroutine write_int1(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: x(:)
    integer(hid_t) :: did, fs, ms
    integer(hsize_t) :: dims(1)
    integer :: err
    dims = shape(x, kind=hsize_t)
    call open_fixed(loc, name, H5T_NATIVE_INTEGER, dims, did, fs)
    call mem_space(dims, ms)
    call h5dwrite_f(did, H5T_NATIVE_INTEGER, x, dims, err, mem_space_id=ms, &
        file_space_id=fs, xfer_prp=dxpl)
    call close_ds(did, fs, ms, name, err)
  end subroutine write_int1

  subroutine write_int2(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: x(:,:)
    integer(hid_t) :: did, fs, ms
    integer(hsize_t) :: dims(2)
    integer :: err
    dims = shape(x, kind=hsize_t)
    call open_fixed(loc, name, H5T_NATIVE_INTEGER, dims, did, fs)
    call mem_space(dims, ms)
    call h5dwrite_f(did, H5T_NATIVE_INTEGER, x, dims, err, mem_space_id=ms, &
        file_space_id=fs, xfer_prp=dxpl)
    call close_ds(did, fs, ms, name, err)
  end subroutine write_int2

  !> Dataset (nglobal, ncomp) [Fortran (ncomp, nglobal)] written collectively: each rank writes
  !! the rows gid(1:n) from x(ncomp, n). Rows that are one increasing run of global indices
  !! (a single rank's rows, the viewing samples) are selected as one block; any other set by a
  !! point selection, which costs HDF5 tens of bytes per value (gigabytes at 1e6 elements).
  subroutine write_rows_any(loc, name, ncomp, n, x, gid, nglobal)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: ncomp, n, nglobal
    real(dp), intent(in) :: x(ncomp*n)
    integer, intent(in) :: gid(n)
    integer(hid_t) :: did, fs, ms
    integer(hsize_t) :: dims(2), mdims(1), start(2), count(2)
    integer(hsize_t), allocatable :: coord(:,:)
    integer :: err, i, c, k, rank
    logical :: run
    rank = 2
    if (ncomp == 1) rank = 1
    dims = [int(ncomp, hsize_t), int(nglobal, hsize_t)]
    if (rank == 1) dims(1) = int(nglobal, hsize_t)
    call h5screate_simple_f(rank, dims(1:rank), fs, err)
    call check(err, 'dataspace '//name)
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, fs, did, err)
    call check(err, 'dataset '//name)
    mdims(1) = int(max(ncomp*n, 1), hsize_t)
    call h5screate_simple_f(1, mdims, ms, err)
    run = n > 0
    do i = 2, n
      if (gid(i) /= gid(1) + i - 1) then
        run = .false.
        exit
      end if
    end do
    if (n == 0) then
      call h5sselect_none_f(fs, err)
      call h5sselect_none_f(ms, err)
    else if (run) then
      start = [0_hsize_t, int(gid(1) - 1, hsize_t)]
      count = [int(ncomp, hsize_t), int(n, hsize_t)]
      if (rank == 1) then
        start(1) = start(2)
        count(1) = count(2)
      end if
      call h5sselect_hyperslab_f(fs, H5S_SELECT_SET_F, start(1:rank), count(1:rank), err)
      call check(err, 'selecting rows of '//name)
    else
      allocate(coord(rank, ncomp*n))
      k = 0
      do i = 1, n
        do c = 1, ncomp
          k = k + 1
          if (rank == 1) then
            coord(1, k) = int(gid(i), hsize_t)
          else
            coord(:, k) = [int(c, hsize_t), int(gid(i), hsize_t)]
          end if
        end do
      end do
      call h5sselect_elements_f(fs, H5S_SELECT_SET_F, rank, int(ncomp*n, size_t), &
          coord, err)
      call check(err, 'selecting rows of '//name)
    end if
    call h5dwrite_f(did, H5T_NATIVE_DOUBLE, x, mdims, err, mem_space_id=ms, &
        file_space_id=fs, xfer_prp=dxpl)
    call close_ds(did, fs, ms, name, err)
  end subroutine write_rows_any

  subroutine write_rows1(loc, name, x, gid, nglobal)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:)
    integer, intent(in) :: gid(:), nglobal
    call write_rows_any(loc, name, 1, size(gid), x, gid, nglobal)
  end subroutine write_rows1

  subroutine write_rows2(loc, name, x, gid, nglobal)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:,:)
    integer, intent(in) :: gid(:), nglobal
    call write_rows_any(loc, name, size(x, 1), size(gid), x, gid, nglobal)
  end subroutine write_rows2

  !> Creates an extendible dataset of records: (ncomp, 0) growing in the last Fortran
  !! dimension (HDF5 shape (nt, ncomp)), or (0) when ncomp = 0. `integer` selects the type.
  subroutine h5u_create_ext(loc, name, ncomp, chunk, is_integer)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: ncomp, chunk
    logical, intent(in), optional :: is_integer
    integer(hid_t) :: sid, did, dcpl, dtype
    integer(hsize_t), allocatable :: dims(:), maxdims(:), cdims(:)
    integer :: err
    dtype = H5T_NATIVE_DOUBLE
    if (present(is_integer)) then
      if (is_integer) dtype = H5T_NATIVE_INTEGER
    end if
    if (ncomp == 0) then
      dims = [0_hsize_t]
      maxdims = [H5S_UNLIMITED_F]
      cdims = [int(chunk, hsize_t)]
    else
      dims = [int(ncomp, hsize_t), 0_hsize_t]
      maxdims = [int(ncomp, hsize_t), H5S_UNLIMITED_F]
      cdims = [int(ncomp, hsize_t), int(chunk, hsize_t)]
    end if
    call h5screate_simple_f(size(dims), dims, sid, err, maxdims)
    call check(err, 'dataspace '//name)
    call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, err)
    call h5pset_chunk_f(dcpl, size(cdims), cdims, err)
    call check(err, 'chunking '//name)
    call h5dcreate_f(loc, name, dtype, sid, did, err, dcpl_id=dcpl)
    call check(err, 'dataset '//name)
    call h5dclose_f(did, err)
    call h5pclose_f(dcpl, err)
    call h5sclose_f(sid, err)
  end subroutine h5u_create_ext

  !> Extends dataset `name` by `nnew` records and returns the file space with the new records
  !! selected on rank 0 (nothing elsewhere).
  subroutine extend(loc, name, rank, ncomp, nnew, did, fs, ms)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: rank, ncomp, nnew
    integer(hid_t), intent(out) :: did, fs, ms
    integer(hsize_t) :: dims(rank), maxdims(rank), start(rank), count(rank)
    integer :: err
    call h5dopen_f(loc, name, did, err)
    call check(err, 'opening '//name)
    call h5dget_space_f(did, fs, err)
    call h5sget_simple_extent_dims_f(fs, dims, maxdims, err)
    call h5sclose_f(fs, err)
    start = 0
    if (rank == 1) then
      start(1) = dims(1)
      dims(1) = dims(1) + nnew
      count = [int(nnew, hsize_t)]
    else
      start(2) = dims(2)
      dims(2) = dims(2) + nnew
      count = [int(ncomp, hsize_t), int(nnew, hsize_t)]
    end if
    call h5dset_extent_f(did, dims, err)
    call check(err, 'extending '//name)
    call h5dget_space_f(did, fs, err)
    call h5sselect_hyperslab_f(fs, H5S_SELECT_SET_F, start, count, err)
    if (.not. env_is_root()) call h5sselect_none_f(fs, err)
    call mem_space(count, ms)
  end subroutine extend

  subroutine append_real1(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:)
    integer(hid_t) :: did, fs, ms
    integer :: err
    if (size(x) == 0) return
    call extend(loc, name, 1, 0, size(x), did, fs, ms)
    call h5dwrite_f(did, H5T_NATIVE_DOUBLE, x, shape(x, kind=hsize_t), err, &
        mem_space_id=ms, file_space_id=fs, xfer_prp=dxpl)
    call close_ds(did, fs, ms, name, err)
  end subroutine append_real1

  subroutine append_int1(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: x(:)
    integer(hid_t) :: did, fs, ms
    integer :: err
    if (size(x) == 0) return
    call extend(loc, name, 1, 0, size(x), did, fs, ms)
    call h5dwrite_f(did, H5T_NATIVE_INTEGER, x, shape(x, kind=hsize_t), err, &
        mem_space_id=ms, file_space_id=fs, xfer_prp=dxpl)
    call close_ds(did, fs, ms, name, err)
  end subroutine append_int1

  subroutine append_real2(loc, name, x)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x(:,:)
    integer(hid_t) :: did, fs, ms
    integer :: err
    if (size(x, 2) == 0) return
    call extend(loc, name, 2, size(x, 1), size(x, 2), did, fs, ms)
    call h5dwrite_f(did, H5T_NATIVE_DOUBLE, x, shape(x, kind=hsize_t), err, &
        mem_space_id=ms, file_space_id=fs, xfer_prp=dxpl)
    call close_ds(did, fs, ms, name, err)
  end subroutine append_real2
end module ictus_io_hdf5_util
