!! The DEM-Util library subroutines of ppOpen-APPL/DEM-Util 1.0, with the original names and
!! argument lists (external, implicit interfaces, as the original). Each runs its stage of the
!! original's pipeline through ppohdem's C API (reference/compat, bit for bit the original):
!!   ppohDEM_loadfileinfo             ./input/input_constants_voxelizer.dat
!!   ppohDEM_v_pre                    read the STL, grid coordinates
!!   ppohDEM_v_makevoxel              placement, object_mesh.stl (rank 0), z-ray voxelisation
!!   ppohDEM_v_distancecalculate_MPI1 Jacobi pass 1                  (log-timings1)
!!   ppohDEM_v_distanceprecise        exact distances in the band    (log-timings2)
!!   ppohDEM_v_distancecalculate_MPI2 Jacobi pass 2                  (log-timings3)
!!   output_data                      this rank's distance_NNNN.dat
!!   ppohDEM_v_exit                   release everything
!! A stage called before its prerequisite stops the program with a message naming both.
!! docs/fortran.md.

subroutine ppohDEM_loadfileinfo(file_info, ftype)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_create
    use, intrinsic :: iso_c_binding, only: c_int32_t
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    integer(kind=kint) :: ftype
    character :: chr
    integer(kind=kint) :: err
    character(len=*), parameter :: input_file = './input/input_constants_voxelizer.dat'

    if (ftype /= 1) then
        write (0,'(a,i0,a)') 'ppohDEM-Error: ppohDEM_loadfileinfo: file type ', ftype, &
            ' is not supported by ppohdem (only 1, the voxelizer input)'
        stop 1
    endif
    ! The original's reads, so that file_info holds what the original holds.
    open (21, file=input_file, status='old', iostat=err)
    if (err /= 0) then
        write (0,'(a)') 'ppohDEM-Error: ppohDEM_loadfileinfo: cannot open ' // input_file
        stop 1
    endif
    file_info%func = 1
    read (21,'(a80)') file_info%input_filename
    read (21,'(a80)') file_info%output_filename
    read (21,*) file_info%gridX, file_info%gridY, file_info%gridZ
    read (21, *, iostat=err) chr, file_info%object_L%x, file_info%object_L%y, file_info%object_L%z
    read (21, *, iostat=err) chr, file_info%object_size%x, file_info%object_size%y, file_info%object_size%z
    read (21, *, iostat=err) chr, file_info%object_origin%x, file_info%object_origin%y, file_info%object_origin%z
    close (21)
    ! ppohdem parses the file again and says what is wrong with it, naming the line.
    call ppohdem_binding_check(ppohdem_util_create(ppohdem_binding_cstr(input_file), int(nprocs, c_int32_t), &
        int(myrank, c_int32_t), file_info%ppohdem_handle), 'ppohDEM_loadfileinfo')
end subroutine

subroutine ppohDEM_v_pre(file_info, meshXYZ, voxel, gridco)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_read_mesh, ppohdem_util_facet_count
    use, intrinsic :: iso_c_binding, only: c_size_t
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_mesh) :: meshXYZ
    type(ppohDEM_voxel) :: voxel
    type(ppohDEM_gridco) :: gridco
    integer(c_size_t) :: facets
    integer(kind=kint) :: i

    call ppohdem_binding_require(file_info%ppohdem_handle, 'ppohDEM_v_pre', 'ppohDEM_loadfileinfo')
    call ppohdem_binding_check(ppohdem_util_read_mesh(file_info%ppohdem_handle), 'ppohDEM_v_pre')
    call ppohdem_binding_check(ppohdem_util_facet_count(file_info%ppohdem_handle, facets), 'ppohDEM_v_pre')
    meshXYZ%n = int(facets)
    meshXYZ%ppohdem_handle = file_info%ppohdem_handle
    voxel%ppohdem_handle = file_info%ppohdem_handle

    voxel%gridX = file_info%gridX
    voxel%gridY = file_info%gridY
    voxel%gridZ = file_info%gridZ
    voxel%Lx = file_info%object_L%x
    voxel%Ly = file_info%object_L%y
    voxel%Lz = file_info%object_L%z
    voxel%W = voxel%Lx / voxel%gridX
    voxel%W2 = voxel%W * voxel%W
    voxel%sizeX = file_info%object_size%x
    voxel%sizeY = file_info%object_size%y
    voxel%sizeZ = file_info%object_size%z
    voxel%posX = file_info%object_origin%x
    voxel%posY = file_info%object_origin%y
    voxel%posZ = file_info%object_origin%z

    ! The rank's x-slab: the first mod(gridX, nprocs) ranks get one more plane.
    quotient = voxel%gridX / nprocs
    remainder = mod(voxel%gridX, nprocs)
    if (myrank < remainder) then
        i_x_start = myrank * (quotient + 1) + 1
        i_x_end = i_x_start + quotient
    else
        i_x_start = myrank * quotient + remainder + 1
        i_x_end = i_x_start + quotient - 1
    endif
    loop_x_start = max(i_x_start, 2)
    loop_x_end = min(i_x_end, voxel%gridX - 1)

    ! Node (i,j,k) at (L/n)(i-1), as the original.
    allocate(gridco%x(voxel%gridX), gridco%y(voxel%gridY), gridco%z(voxel%gridZ))
    do i = 1, voxel%gridX
        gridco%x(i) = (voxel%Lx / voxel%gridX) * (i - 1)
    enddo
    do i = 1, voxel%gridY
        gridco%y(i) = (voxel%Ly / voxel%gridY) * (i - 1)
    enddo
    do i = 1, voxel%gridZ
        gridco%z(i) = (voxel%Lz / voxel%gridZ) * (i - 1)
    enddo
    allocate(voxel%value_3D(voxel%gridX, voxel%gridY, voxel%gridZ))
    allocate(voxel%distance_3D(voxel%gridX, voxel%gridY, voxel%gridZ))
    voxel%value_3D = 0
    voxel%distance_3D = 10 * voxel%Lx
end subroutine

!> Copies ppohdem's current field into voxel%distance_3D and voxel%value_3D.
subroutine ppohdem_binding_fetch_field(voxel, where)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_field
    use, intrinsic :: iso_c_binding, only: c_size_t
    implicit none
    type(ppohDEM_voxel) :: voxel
    character(len=*) :: where
    call ppohdem_binding_check(ppohdem_util_field(voxel%ppohdem_handle, voxel%distance_3D, voxel%value_3D, &
        int(size(voxel%distance_3D), c_size_t)), where)
end subroutine

subroutine ppohDEM_v_makevoxel(file_info, meshXYZ, voxel, gridco)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_voxelize
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_mesh) :: meshXYZ
    type(ppohDEM_voxel) :: voxel
    type(ppohDEM_gridco) :: gridco

    call ppohdem_binding_require(voxel%ppohdem_handle, 'ppohDEM_v_makevoxel', 'ppohDEM_v_pre')
    ! object_mesh.stl goes to output_filename // "object_mesh.stl" (line 2 is a prefix).
    call ppohdem_binding_check(ppohdem_util_voxelize(voxel%ppohdem_handle, &
        ppohdem_binding_cstr(file_info%output_filename)), 'ppohDEM_v_makevoxel')
    call ppohdem_binding_fetch_field(voxel, 'ppohDEM_v_makevoxel')
end subroutine

!> The original's timing log format: (1I3,F16.6) per phase, then (1A,F16.6) 'Total '.
subroutine ppohdem_binding_timing_log(filename, timings, phases)
    use ppohDEM_util
    implicit none
    character(len=*) :: filename
    integer(kind=kint) :: phases
    real(kind=kreal) :: timings(0:phases)
    integer(kind=kint) :: i
    if (myrank /= 0) return
    open (1001, file=filename, status='unknown')
    do i = 1, phases
        write (1001,"(1I3,F16.6)") i, timings(i) - timings(i-1)
    end do
    write (1001,"(1A,F16.6)") 'Total ', timings(phases) - timings(0)
    close (1001)
end subroutine

!> One Jacobi pass: pass 1 after the voxelisation, pass 2 after the exact band (the original's
!> ppohDEM_v_distancecalculate_MPI, of which _MPI1 and _MPI2 are copies with other log names).
subroutine ppohDEM_v_distancecalculate_MPI(voxel)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_pass1, ppohdem_util_pass2, ppohdem_util_exact_band
    implicit none
    type(ppohDEM_voxel) :: voxel
    call ppohdem_binding_require(voxel%ppohdem_handle, 'ppohDEM_v_distancecalculate_MPI', 'ppohDEM_v_pre')
    call ppohdem_binding_jacobi(voxel, 'ppohDEM_v_distancecalculate_MPI', 'log-timings1', 0)
end subroutine

subroutine ppohDEM_v_distancecalculate_MPI1(voxel)
    use ppohDEM_util
    implicit none
    type(ppohDEM_voxel) :: voxel
    call ppohdem_binding_require(voxel%ppohdem_handle, 'ppohDEM_v_distancecalculate_MPI1', 'ppohDEM_v_pre')
    call ppohdem_binding_jacobi(voxel, 'ppohDEM_v_distancecalculate_MPI1', 'log-timings1', 1)
end subroutine

subroutine ppohDEM_v_distancecalculate_MPI2(voxel)
    use ppohDEM_util
    implicit none
    type(ppohDEM_voxel) :: voxel
    call ppohdem_binding_require(voxel%ppohdem_handle, 'ppohDEM_v_distancecalculate_MPI2', 'ppohDEM_v_pre')
    call ppohdem_binding_jacobi(voxel, 'ppohDEM_v_distancecalculate_MPI2', 'log-timings3', 2)
end subroutine

!> pass = 1 or 2, or 0: whichever is next. Timing phases (cpu_time, rank 0): 1 setup, 2 the
!> sweeps and boundary extrapolation, 3 copying the field into voxel%distance_3D, 4 barrier.
subroutine ppohdem_binding_jacobi(voxel, where, log_name, pass)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_pass1, ppohdem_util_pass2
    implicit none
    type(ppohDEM_voxel) :: voxel
    character(len=*) :: where, log_name
    integer(kind=kint) :: pass, status
    real(kind=kreal) :: timings(0:4)
    call cpu_time(timings(0))
    call cpu_time(timings(1))
    if (pass == 1) then
        status = ppohdem_util_pass1(voxel%ppohdem_handle)
    else if (pass == 2) then
        status = ppohdem_util_pass2(voxel%ppohdem_handle)
    else
        status = ppohdem_util_pass1(voxel%ppohdem_handle)
        if (status /= 0) status = ppohdem_util_pass2(voxel%ppohdem_handle)
    endif
    call ppohdem_binding_check(status, where)
    call cpu_time(timings(2))
    call ppohdem_binding_fetch_field(voxel, where)
    call cpu_time(timings(3))
    if (nprocs > 1) call MPI_BARRIER(MPI_COMM_WORLD, ierr)
    call cpu_time(timings(4))
    call ppohdem_binding_timing_log(log_name, timings, 4)
end subroutine

!> Timing phases (cpu_time, rank 0): 1 setup, 2 the band's exact distances, 3 copying the
!> field, 4-6 unused (0), kept for the original's 6-line log.
subroutine ppohDEM_v_distanceprecise(voxel, meshXYZ, gridco)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_exact_band
    implicit none
    type(ppohDEM_voxel) :: voxel
    type(ppohDEM_mesh) :: meshXYZ
    type(ppohDEM_gridco) :: gridco
    real(kind=kreal) :: timings(0:6)
    call ppohdem_binding_require(voxel%ppohdem_handle, 'ppohDEM_v_distanceprecise', 'ppohDEM_v_pre')
    call cpu_time(timings(0))
    call cpu_time(timings(1))
    call ppohdem_binding_check(ppohdem_util_exact_band(voxel%ppohdem_handle), 'ppohDEM_v_distanceprecise')
    call cpu_time(timings(2))
    call ppohdem_binding_fetch_field(voxel, 'ppohDEM_v_distanceprecise')
    call cpu_time(timings(3))
    timings(4:6) = timings(3)
    call ppohdem_binding_timing_log('log-timings2', timings, 6)
end subroutine

subroutine output_data(file_info, voxel)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_write
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_voxel) :: voxel
    call ppohdem_binding_require(voxel%ppohdem_handle, 'output_data', 'ppohDEM_v_pre')
    call ppohdem_binding_check(ppohdem_util_write(voxel%ppohdem_handle, &
        ppohdem_binding_cstr(file_info%output_filename)), 'output_data')
end subroutine

subroutine ppohDEM_v_exit(meshXYZ, voxel, gridco)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_util_destroy
    use, intrinsic :: iso_c_binding, only: c_null_ptr
    implicit none
    type(ppohDEM_mesh) :: meshXYZ
    type(ppohDEM_voxel) :: voxel
    type(ppohDEM_gridco) :: gridco
    integer :: status
    call ppohdem_binding_require(voxel%ppohdem_handle, 'ppohDEM_v_exit', 'ppohDEM_v_pre')
    status = ppohdem_util_destroy(voxel%ppohdem_handle)
    voxel%ppohdem_handle = c_null_ptr
    meshXYZ%ppohdem_handle = c_null_ptr
    if (associated(voxel%value_3D)) deallocate(voxel%value_3D)
    if (associated(voxel%distance_3D)) deallocate(voxel%distance_3D)
    if (associated(gridco%x)) deallocate(gridco%x, gridco%y, gridco%z)
end subroutine
