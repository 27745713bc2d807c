! Error path: pass 2 (ppohDEM_v_distancecalculate_MPI2) right after ppohDEM_v_makevoxel.
program util_out_of_order
    use ppohDEM_util
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_mesh) :: meshXYZ
    type(ppohDEM_voxel) :: voxel
    type(ppohDEM_gridco) :: gridco
    call MPI_INIT(ierr)
    call MPI_COMM_SIZE(MPI_COMM_WORLD, nprocs, ierr)
    call MPI_COMM_RANK(MPI_COMM_WORLD, myrank, ierr)
    call ppohDEM_loadfileinfo(file_info, 1)
    call ppohDEM_v_pre(file_info, meshXYZ, voxel, gridco)
    call ppohDEM_v_makevoxel(file_info, meshXYZ, voxel, gridco)
    call ppohDEM_v_distancecalculate_MPI2(voxel)
    call MPI_FINALIZE(ierr)
end program
